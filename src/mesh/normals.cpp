// SPDX-License-Identifier: Apache-2.0
// Area-weighted vertex normals, summed in double: a float sum over thousands of faces drifts.
#include "lasmesh/normals.hpp"

#include <cmath>

namespace lasmesh {

namespace {

// Per vertex, the sum of the normals of the faces around it, each as long as twice its area.
std::vector<std::array<double, 3>> face_normal_sums(const Mesh& mesh) {
    std::vector<std::array<double, 3>> sum(mesh.positions.size(), {0, 0, 0});
    for (const auto& t : mesh.triangles) {
        const auto& a = mesh.positions[t[0]];
        const auto& b = mesh.positions[t[1]];
        const auto& c = mesh.positions[t[2]];
        const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
        const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
        const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        for (const std::uint32_t vertex : t)
            for (int k = 0; k < 3; ++k) sum[vertex][k] += n[k];
    }
    return sum;
}

std::array<float, 3> unit(const std::array<double, 3>& s) {
    const double length = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    return length > 0 ? std::array<float, 3>{float(s[0] / length), float(s[1] / length), float(s[2] / length)}
                      : std::array<float, 3>{0, 0, 1};
}

} // namespace

void compute_vertex_normals(Mesh& mesh) {
    const auto sum = face_normal_sums(mesh);
    mesh.normals.resize(mesh.positions.size());
    for (std::size_t i = 0; i < sum.size(); ++i) mesh.normals[i] = unit(sum[i]);
}

void agree_normals_with_faces(Mesh& mesh) {
    if (mesh.normals.size() != mesh.positions.size()) return compute_vertex_normals(mesh);
    const auto sum = face_normal_sums(mesh);
    for (std::size_t i = 0; i < sum.size(); ++i) {
        const auto& n = mesh.normals[i];
        if (n[0] * sum[i][0] + n[1] * sum[i][1] + n[2] * sum[i][2] <= 0) mesh.normals[i] = unit(sum[i]);
    }
}

} // namespace lasmesh
