// SPDX-License-Identifier: Apache-2.0
// The 256 marching-cubes cases, derived at first use from one rule rather than typed in:
// on every cube face the surface crosses the edges whose corners disagree, and on an ambiguous
// face (inside corners diagonal) the inside corners are kept apart. Both cubes that share a face
// apply the rule to the same four corners, so neighbouring cells always agree: no cracks.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace lasmesh {

// Corner c of a cube is at (c & 1, (c >> 1) & 1, (c >> 2) & 1). Edge e runs along axis e / 4
// from corner edge_corners[e][0] to edge_corners[e][1] (the lower corner first).
struct CubeEdges {
    std::array<std::array<std::uint8_t, 2>, 12> corners;
};
const CubeEdges& cube_edges();

// Triangles of each case, as edge triples. Case bit c is set when corner c is inside (above the
// iso value). Triangles wind counter-clockwise seen from outside, so (b - a) x (c - a) points
// from inside (dense) to outside.
struct CaseTable {
    std::array<std::vector<std::array<std::uint8_t, 3>>, 256> triangles;
};
const CaseTable& case_table();

} // namespace lasmesh
