// SPDX-License-Identifier: Apache-2.0
// OutsideSpace: the walls round the surface cells, then a flood from the top through the rest.
#include "mesh/outside_space.hpp"

#include <algorithm>
#include <cmath>

namespace lasmesh {

int OutsideSpace::voxel_shift(const std::array<std::uint32_t, 3>& dims) {
    int shift = 0;
    while ((std::int64_t{std::max({dims[0], dims[1], dims[2]})} >> shift) > 256) ++shift;
    return shift;
}

OutsideSpace::OutsideSpace(const std::array<std::uint32_t, 3>& dims,
                           const std::vector<std::array<std::int64_t, 3>>& surface_cells)
    : shift_(voxel_shift(dims)) {
    for (int a = 0; a < 3; ++a) size_[a] = ((std::int64_t{dims[a]} + (1 << shift_) - 1) >> shift_) + 2;
    std::vector<char> wall(static_cast<std::size_t>(size_[0] * size_[1] * size_[2]), 0);
    // A voxel holding a surface cell, and its six neighbours, are walls: gaps of a voxel close.
    for (const auto& c : surface_cells) {
        const std::array<std::int64_t, 3> v{(c[0] >> shift_) + 1, (c[1] >> shift_) + 1, (c[2] >> shift_) + 1};
        wall[index(v)] = 1;
        for (int a = 0; a < 3; ++a)
            for (const int d : {-1, 1}) {
                std::array<std::int64_t, 3> w = v;
                w[a] += d;
                if (w[a] >= 0 && w[a] < size_[a]) wall[index(w)] = 1;
            }
    }
    reached_.assign(wall.size(), 0);
    std::vector<std::array<std::int64_t, 3>> queue;
    for (std::int64_t y = 0; y < size_[1]; ++y)
        for (std::int64_t x = 0; x < size_[0]; ++x)
            if (const std::array<std::int64_t, 3> v{x, y, size_[2] - 1}; !wall[index(v)])
                reached_[index(v)] = 1, queue.push_back(v);
    for (std::size_t i = 0; i < queue.size(); ++i)
        for (int a = 0; a < 3; ++a)
            for (const int d : {-1, 1}) {
                std::array<std::int64_t, 3> w = queue[i];
                w[a] += d;
                if (w[a] < 0 || w[a] >= size_[a] || wall[index(w)] || reached_[index(w)]) continue;
                reached_[index(w)] = 1;
                queue.push_back(w);
            }
}

bool OutsideSpace::open(const std::array<double, 3>& point, const std::array<double, 3>& direction, double cell) const {
    const double voxel = cell * double(1 << shift_);
    for (const double steps : {2.5, 3.5}) {
        std::array<std::int64_t, 3> v{};
        for (int a = 0; a < 3; ++a) {
            v[a] = static_cast<std::int64_t>(std::floor((point[a] + direction[a] * steps * voxel) / voxel)) + 1;
            if (v[a] < 0 || v[a] >= size_[a]) return a != 2 || v[a] >= size_[a]; // past the sides or the top: outside
        }
        if (v[2] == 0) return false; // below the grid's floor: not outside (the bottom margin only carries the flood)
        if (reached_[index(v)]) return true;
    }
    return false;
}

std::vector<double> outside_votes(const Mesh& mesh, const OutsideSpace& outside, double cell) {
    using Vec = std::array<double, 3>;
    std::vector<double> votes(mesh.triangles.size(), 0);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        Vec p[3];
        for (int k = 0; k < 3; ++k) p[k] = {mesh.positions[t[k]][0], mesh.positions[t[k]][1], mesh.positions[t[k]][2]};
        const Vec u{p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]},
            w{p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        Vec normal{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        const double twice_area = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
        if (!(twice_area > 0)) continue;
        for (double& c : normal) c /= twice_area;
        const Vec centre{(p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3,
                         (p[0][2] + p[1][2] + p[2][2]) / 3};
        const bool front = outside.open(centre, normal, cell),
                   back = outside.open(centre, Vec{-normal[0], -normal[1], -normal[2]}, cell);
        if (front != back) votes[i] = front ? twice_area : -twice_area;
    }
    return votes;
}

} // namespace lasmesh
