// Connected pieces by union-find over vertices, then one pass to keep or drop each triangle.
#include "lasmesh/mesh/mesh_pieces.hpp"

#include "lasmesh/error.hpp"

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

} // namespace

PieceCount remove_small_pieces(Mesh& mesh, MinPiece min_piece) {
    const std::size_t nv = mesh.positions.size();
    std::vector<std::uint32_t> parent(nv);
    std::iota(parent.begin(), parent.end(), 0u);
    for (const auto& t : mesh.triangles)
        for (int c = 1; c < 3; ++c) {
            const std::uint32_t a = find_root(parent, t[0]), b = find_root(parent, t[c]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b); // the smaller id roots: deterministic
        }

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
