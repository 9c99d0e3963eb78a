// SPDX-License-Identifier: Apache-2.0
// Reading triangle meshes from PLY: ours, and any other writer's (ASCII or binary of either byte
// order, any numeric property types, polygons split into triangle fans).
#pragma once

#include "lasmesh/mesh.hpp"

#include <string>

namespace lasmesh {

// Reads `path`. Vertex x, y, z are required; red, green, blue are read when present (8-bit;
// nx, ny, nz too, as they are;
// wider types are scaled to 8 bits); faces come from the list property "vertex_indices" (or
// "vertex_index"). lasmesh's own `comment origin X Y Z` and `comment cell_size H` are restored
// into the mesh. Throws Error (input) naming the file, the byte offset and what was expected.
Mesh read_ply(const std::string& path);

} // namespace lasmesh
