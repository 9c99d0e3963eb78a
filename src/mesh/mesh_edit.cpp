// SPDX-License-Identifier: Apache-2.0
// remove_unused_vertices, keep_triangles_in_blocks, append_mesh, connected_parts, turn_over.
#include "mesh/mesh_edit.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lasmesh {

void remove_unused_vertices(Mesh& mesh) {
    constexpr std::uint32_t unused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> remap(mesh.positions.size(), unused);
    for (const auto& t : mesh.triangles)
        for (const std::uint32_t v : t) remap[v] = 0;
    std::uint32_t kept = 0;
    for (std::size_t v = 0; v < remap.size(); ++v) {
        if (remap[v] == unused) continue;
        remap[v] = kept;
        mesh.positions[kept] = mesh.positions[v];
        if (!mesh.colors.empty()) mesh.colors[kept] = mesh.colors[v];
        if (!mesh.normals.empty()) mesh.normals[kept] = mesh.normals[v];
        ++kept;
    }
    mesh.positions.resize(kept);
    if (!mesh.colors.empty()) mesh.colors.resize(kept);
    if (!mesh.normals.empty()) mesh.normals.resize(kept);
    for (auto& t : mesh.triangles)
        for (std::uint32_t& v : t) v = remap[v];
}

void keep_triangles_in_blocks(Mesh& mesh, const GridSpec& grid, int shift, const std::vector<std::uint64_t>& blocks,
                              bool inside) {
    const double block_edge = std::ldexp(grid.cell_size, shift);
    std::array<std::uint64_t, 3> count{};
    for (int a = 0; a < 3; ++a) count[a] = (std::uint64_t{grid.dims[a]} + (1u << shift) - 1) >> shift;
    std::vector<char> keep(mesh.triangles.size());
    tbb::parallel_for(std::size_t{0}, mesh.triangles.size(), [&](std::size_t i) {
        const auto& t = mesh.triangles[i];
        std::array<std::uint64_t, 3> at{};
        for (int a = 0; a < 3; ++a) {
            const double c =
                (double(mesh.positions[t[0]][a]) + double(mesh.positions[t[1]][a]) + double(mesh.positions[t[2]][a])) /
                3;
            at[a] = static_cast<std::uint64_t>(
                std::clamp(std::floor(c / block_edge), 0.0, static_cast<double>(count[a] - 1)));
        }
        const std::uint64_t key = (at[2] * count[1] + at[1]) * count[0] + at[0];
        keep[i] = std::binary_search(blocks.begin(), blocks.end(), key) == inside;
    });
    std::size_t kept = 0;
    for (std::size_t i = 0; i < keep.size(); ++i)
        if (keep[i]) mesh.triangles[kept++] = mesh.triangles[i];
    mesh.triangles.resize(kept);
    remove_unused_vertices(mesh);
}

void append_mesh(Mesh& mesh, const Mesh& more) {
    const auto first = static_cast<std::uint32_t>(mesh.positions.size());
    const bool colors = !mesh.colors.empty() && !more.colors.empty();
    const bool normals = !mesh.normals.empty() && !more.normals.empty();
    mesh.positions.insert(mesh.positions.end(), more.positions.begin(), more.positions.end());
    if (colors)
        mesh.colors.insert(mesh.colors.end(), more.colors.begin(), more.colors.end());
    else
        mesh.colors.clear();
    if (normals)
        mesh.normals.insert(mesh.normals.end(), more.normals.begin(), more.normals.end());
    else
        mesh.normals.clear();
    for (auto t : more.triangles) {
        for (std::uint32_t& v : t) v += first;
        mesh.triangles.push_back(t);
    }
}

std::vector<std::uint32_t> connected_parts(const Mesh& mesh) {
    std::vector<std::uint32_t> root(mesh.positions.size());
    for (std::uint32_t v = 0; v < root.size(); ++v) root[v] = v;
    const auto find = [&](std::uint32_t v) {
        while (root[v] != v) v = root[v] = root[root[v]]; // path halving
        return v;
    };
    for (const auto& t : mesh.triangles)
        for (int k = 1; k < 3; ++k) {
            const std::uint32_t a = find(t[0]), b = find(t[k]);
            if (a != b) root[std::max(a, b)] = std::min(a, b); // the smaller number roots
        }
    // Every link points to a smaller number, so one ascending pass leaves each vertex on its root.
    for (std::uint32_t v = 0; v < root.size(); ++v) root[v] = root[root[v]];
    return root;
}

void turn_over(Mesh& mesh, const std::vector<char>& turned) {
    for (auto& t : mesh.triangles)
        if (turned[t[0]]) std::swap(t[1], t[2]);
    for (std::uint32_t v = 0; v < turned.size() && !mesh.normals.empty(); ++v)
        if (turned[v])
            for (float& c : mesh.normals[v]) c = -c;
}

} // namespace lasmesh
