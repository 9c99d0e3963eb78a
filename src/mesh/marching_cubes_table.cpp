// SPDX-License-Identifier: Apache-2.0
// Derivation of the case table: face segments by the separate-inside rule, chained into closed
// polygons, fanned into triangles. See the header for the conventions.
#include "mesh/marching_cubes_table.hpp"

#include <algorithm>

namespace lasmesh {

namespace {

CubeEdges make_edges() {
    CubeEdges edges{};
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (int k = 0; k < 4; ++k) {
            const int low = ((k & 1) << u) | (((k >> 1) & 1) << v);
            edges.corners[axis * 4 + k] = {static_cast<std::uint8_t>(low),
                                           static_cast<std::uint8_t>(low | (1 << axis))};
        }
    }
    return edges;
}

int edge_between(const CubeEdges& edges, int a, int b) {
    for (int e = 0; e < 12; ++e)
        if ((edges.corners[e][0] == a && edges.corners[e][1] == b) ||
            (edges.corners[e][0] == b && edges.corners[e][1] == a))
            return e;
    return -1;
}

// Whether cube edges e and f lie on a common face of the cube.
bool share_face(const CubeEdges& edges, int e, int f) {
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            auto on_face = [&](int edge) {
                return edge / 4 != axis && ((edges.corners[edge][0] >> axis) & 1) == side &&
                       ((edges.corners[edge][1] >> axis) & 1) == side;
            };
            if (on_face(e) && on_face(f)) return true;
        }
    return false;
}

// The fan apex for a polygon: one whose chords never join two points of the same cube face. Such
// a chord would lie in the face, where the neighbouring cube may draw the same chord: the edge
// would then belong to four triangles.
std::size_t fan_apex(const CubeEdges& edges, const std::vector<int>& polygon) {
    const std::size_t n = polygon.size();
    for (std::size_t apex = 0; apex < n; ++apex) {
        bool clean = true;
        for (std::size_t i = 2; i + 1 < n && clean; ++i)
            clean = !share_face(edges, polygon[apex], polygon[(apex + i) % n]);
        if (clean) return apex;
    }
    return 0;
}

CaseTable make_table() {
    const CubeEdges& edges = cube_edges();
    CaseTable table;
    for (int mask = 0; mask < 256; ++mask) {
        auto inside = [&](int corner) { return (mask >> corner) & 1; };
        // next[e]: the edge that follows edge e on the surface's boundary curve, or -1.
        std::array<int, 12> next;
        next.fill(-1);
        for (int axis = 0; axis < 3; ++axis) {
            for (int side = 0; side < 2; ++side) {
                // The face's corners counter-clockwise as seen from outside the cube: (u, v) in
                // order (0,0) (1,0) (1,1) (0,1) is counter-clockwise seen from +axis.
                const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                std::array<int, 4> ring;
                const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                for (int i = 0; i < 4; ++i) ring[i] = (side << axis) | (uv[i][0] << u) | (uv[i][1] << v);
                if (side == 0) std::reverse(ring.begin(), ring.end());
                // Walking the ring, pair each crossing into the inside with the next crossing out
                // of it: the inside corners end up on the segment's right, seen from outside,
                // and on an ambiguous face each inside corner is cut off on its own.
                int entered = -1;
                for (int step = 0; step < 8; ++step) {
                    const int a = ring[step % 4], b = ring[(step + 1) % 4];
                    if (inside(a) == inside(b)) continue;
                    const int e = edge_between(edges, a, b);
                    if (!inside(a)) {
                        entered = e;
                    } else if (entered >= 0) {
                        next[entered] = e;
                        entered = -1;
                        if (step >= 4) break;
                    }
                }
            }
        }
        // Each crossed edge lies on two faces, so it starts one segment and ends another: the
        // segments form closed polygons. Fan each one into triangles.
        std::array<bool, 12> used{};
        for (int start = 0; start < 12; ++start) {
            if (next[start] < 0 || used[start]) continue;
            std::vector<int> polygon;
            for (int e = start; !used[e]; e = next[e]) {
                used[e] = true;
                polygon.push_back(e);
            }
            std::rotate(polygon.begin(), polygon.begin() + fan_apex(edges, polygon), polygon.end());
            for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
                table.triangles[mask].push_back({static_cast<std::uint8_t>(polygon[0]),
                                                 static_cast<std::uint8_t>(polygon[i]),
                                                 static_cast<std::uint8_t>(polygon[i + 1])});
        }
    }
    return table;
}

} // namespace

const CubeEdges& cube_edges() {
    static const CubeEdges edges = make_edges();
    return edges;
}

const CaseTable& case_table() {
    static const CaseTable table = make_table();
    return table;
}

} // namespace lasmesh
