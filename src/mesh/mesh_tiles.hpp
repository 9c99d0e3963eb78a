// SPDX-License-Identifier: Apache-2.0
// A mesh cut into the tiles of a square lattice in x and y (a level of a tileset): each triangle
// goes to the tile that holds its centroid, with copies of the vertices it uses. A vertex on a
// border is copied, bit for bit, into every tile that uses it, so the tiles of a level meet
// without cracks: welded by position they give back the mesh's own edges, no new border.
#pragma once

#include "lasmesh/mesh.hpp"

#include <cstdint>
#include <vector>

namespace lasmesh {

struct MeshTile {
    std::int64_t x = 0, y = 0; // the tile's place in the lattice: corner + (x, y) * edge
    Mesh mesh;                 // in the mesh's frame (the same origin); colours and normals kept
};

// The non-empty tiles of `mesh` on the lattice whose tile (0, 0) starts at `corner` (world x, y),
// whose tiles are `edge` long and that has `count` tiles an axis, in order of y, then x. A
// triangle whose centroid lies past the lattice (a plate's face moved out from a sheet at the
// grid's edge) goes to the nearest tile.
std::vector<MeshTile> split_into_tiles(const Mesh& mesh, const Vec3& corner, double edge, std::int64_t count);

} // namespace lasmesh
