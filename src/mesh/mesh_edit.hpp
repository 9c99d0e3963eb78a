// SPDX-License-Identifier: Apache-2.0
// Small edits of a mesh as a whole: unused vertices dropped, triangles kept by where they lie in
// a grid's bricks, one mesh appended to another, connected parts found and turned over.
#pragma once

#include "lasmesh/grid.hpp"
#include "lasmesh/mesh.hpp"

#include <cstdint>
#include <vector>

namespace lasmesh {

// Drops the vertices no triangle uses and renumbers the rest in their old order.
void remove_unused_vertices(Mesh& mesh);

// Keeps the triangles whose centroid lies in one of `blocks` (keys of the blocks of 2^shift cells
// an edge of `grid`, ascending, as thin_parts.hpp's blocks_around numbers them; the mesh's
// positions relative to grid.origin) when `inside`, or in none of them when not; their order and
// the order of the vertices kept stay.
void keep_triangles_in_blocks(Mesh& mesh, const GridSpec& grid, int shift, const std::vector<std::uint64_t>& blocks,
                              bool inside);

// Appends `more` (the same origin) to `mesh`: its vertices after mesh's, its triangles after.
// Colours and normals stay only when both have them.
void append_mesh(Mesh& mesh, const Mesh& more);

// The connected part of each vertex (vertices joined by triangles), named by the smallest vertex
// number in it.
std::vector<std::uint32_t> connected_parts(const Mesh& mesh);

// Turns over the triangles whose first corner is marked in `turned` (their winding) and negates
// the normals of the marked vertices: meant for whole connected parts, whose corners agree.
void turn_over(Mesh& mesh, const std::vector<char>& turned);

} // namespace lasmesh
