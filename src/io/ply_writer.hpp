// SPDX-License-Identifier: Apache-2.0
// PLY output: binary little-endian (default) or ASCII; vertex x, y, z (float, relative to the
// mesh origin), float nx, ny, nz when the mesh has normals, and uchar red, green, blue when it has
// colour; faces as
// `list uchar int vertex_indices`. The origin is recorded as `comment origin X Y Z`.
#pragma once

#include "lasmesh/mesh.hpp"

#include <string>

namespace lasmesh {

class OutputFile;

// Writes through a temporary file renamed at the end; throws Error (output).
void write_ply(const Mesh& mesh, const std::string& path, bool ascii = false);

// Writes the PLY into `out` without committing it (build_mesh commits all outputs together).
void write_ply(const Mesh& mesh, OutputFile& out, bool ascii = false);

} // namespace lasmesh
