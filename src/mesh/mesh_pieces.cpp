// SPDX-License-Identifier: Apache-2.0
// Connected pieces by union-find over vertices, then one pass to keep or drop each triangle.
#include "lasmesh/mesh_pieces.hpp"

#include "lasmesh/error.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace lasmesh {

namespace {

struct Box {
    std::array<double, 3> lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::infinity()};
    std::array<double, 3> hi{-lo[0], -lo[1], -lo[2]};
    void add(const std::array<float, 3>& p) {
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], double(p[a])), hi[a] = std::max(hi[a], double(p[a]));
    }
    void add(const Box& b) {
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], b.lo[a]), hi[a] = std::max(hi[a], b.hi[a]);
    }
    double diagonal() const {
        if (lo[0] > hi[0]) return 0;
        return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    }
};

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]]; // path halving
    return v;
}

void join(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
    a = find_root(parent, a), b = find_root(parent, b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b); // the smaller id roots: deterministic
}

// Pieces whose open borders come within a cell of each other are one piece: the sheets of
// surfaces that meet at a sharp edge (a container's wall and roof) are meshed apart, but are no
// outlier. Border vertices (on an edge one triangle uses) are filed by cell and compared with
// those of the 27 cells around.
void join_touching_pieces(const Mesh& mesh, std::vector<std::uint32_t>& parent) {
    const double cell = mesh.cell_size;
    if (!(cell > 0)) return;
    std::vector<std::uint64_t> edges;
    edges.reserve(3 * mesh.triangles.size());
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t a = t[k], b = t[(k + 1) % 3];
            edges.push_back(std::min(a, b) << 32 | std::max(a, b));
        }
    tbb::parallel_sort(edges.begin(), edges.end());
    std::vector<std::uint32_t> border;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if (j - i == 1)
            border.push_back(std::uint32_t(edges[i] >> 32)), border.push_back(std::uint32_t(edges[i] & 0xFFFFFFFFu));
        i = j;
    }
    std::vector<std::uint64_t>().swap(edges);
    tbb::parallel_sort(border.begin(), border.end());
    border.erase(std::unique(border.begin(), border.end()), border.end());
    // (cell key, vertex), sorted: the vertices of a cell are a run.
    const auto key = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
        return (std::uint64_t(x & 0x1FFFFF) << 42) | (std::uint64_t(y & 0x1FFFFF) << 21) | std::uint64_t(z & 0x1FFFFF);
    };
    const auto cell_of = [&](std::uint32_t v, int a) {
        return static_cast<std::int64_t>(std::floor(mesh.positions[v][a] / cell));
    };
    std::vector<std::pair<std::uint64_t, std::uint32_t>> filed;
    filed.reserve(border.size());
    for (const std::uint32_t v : border) filed.emplace_back(key(cell_of(v, 0), cell_of(v, 1), cell_of(v, 2)), v);
    tbb::parallel_sort(filed.begin(), filed.end());
    for (const std::uint32_t v : border) {
        const std::int64_t x = cell_of(v, 0), y = cell_of(v, 1), z = cell_of(v, 2);
        for (std::int64_t dz = -1; dz <= 1; ++dz)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dx = -1; dx <= 1; ++dx) {
                    const std::uint64_t k = key(x + dx, y + dy, z + dz);
                    for (auto it = std::lower_bound(filed.begin(), filed.end(),
                                                    std::pair<std::uint64_t, std::uint32_t>{k, 0});
                         it != filed.end() && it->first == k; ++it) {
                        const auto& p = mesh.positions[v];
                        const auto& q = mesh.positions[it->second];
                        const double d2 = (double(p[0]) - q[0]) * (double(p[0]) - q[0]) +
                                          (double(p[1]) - q[1]) * (double(p[1]) - q[1]) +
                                          (double(p[2]) - q[2]) * (double(p[2]) - q[2]);
                        if (d2 <= cell * cell) join(parent, v, it->second);
                    }
                }
    }
}

} // namespace

PieceCount remove_small_pieces(Mesh& mesh, MinPiece min_piece) {
    const std::size_t nv = mesh.positions.size();
    std::vector<std::uint32_t> parent(nv);
    std::iota(parent.begin(), parent.end(), 0u);
    for (const auto& t : mesh.triangles)
        for (int c = 1; c < 3; ++c) join(parent, t[0], t[c]);

    join_touching_pieces(mesh, parent);
    // Every link points to a smaller id, so one ascending pass leaves each vertex on its root.
    for (std::uint32_t v = 0; v < nv; ++v) parent[v] = parent[parent[v]];
    std::vector<Box> boxes(nv); // indexed by root vertex
    Box all;
    for (std::uint32_t v = 0; v < nv; ++v) boxes[parent[v]].add(mesh.positions[v]);
    PieceCount count;
    for (std::uint32_t v = 0; v < nv; ++v)
        if (parent[v] == v) ++count.pieces, all.add(boxes[v]);
    count.min_diagonal = min_piece.relative ? min_piece.value * all.diagonal() : min_piece.value;
    if (count.min_diagonal <= 0) return count;

    std::vector<std::uint32_t> new_id(nv, std::numeric_limits<std::uint32_t>::max());
    std::uint32_t kept = 0;
    for (std::uint32_t v = 0; v < nv; ++v) {
        const std::uint32_t root = parent[v];
        if (root == v && boxes[v].diagonal() < count.min_diagonal) ++count.removed;
        if (boxes[root].diagonal() >= count.min_diagonal) {
            mesh.positions[kept] = mesh.positions[v];
            if (!mesh.colors.empty()) mesh.colors[kept] = mesh.colors[v];
            if (!mesh.normals.empty()) mesh.normals[kept] = mesh.normals[v];
            new_id[v] = kept++;
        }
    }
    mesh.positions.resize(kept);
    if (!mesh.colors.empty()) mesh.colors.resize(kept);
    if (!mesh.normals.empty()) mesh.normals.resize(kept);
    std::size_t t_kept = 0;
    for (const auto& t : mesh.triangles)
        if (new_id[t[0]] != std::numeric_limits<std::uint32_t>::max())
            mesh.triangles[t_kept++] = {new_id[t[0]], new_id[t[1]], new_id[t[2]]};
    count.triangles_removed = mesh.triangles.size() - t_kept;
    mesh.triangles.resize(t_kept);
    return count;
}

} // namespace lasmesh
