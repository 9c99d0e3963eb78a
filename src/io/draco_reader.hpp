// SPDX-License-Identifier: Apache-2.0
// Reading back the .drc files lasmesh writes (and other Draco meshes), into a Mesh in the file's
// local frame: for the tests and for `lasmesh compare`. The .glb reader is in gltf_reader.hpp.
#pragma once

#include "lasmesh/mesh.hpp"

#include <string>
#include <string_view>

namespace lasmesh {

// A Draco bitstream to a Mesh: POSITION, COLOR when present (8-bit values are sRGB and kept,
// 16-bit values are linear and converted back to 8-bit sRGB), the triangles, and the origin and
// cell size from the "origin" and "cell_size" metadata (zero when absent). Vertex and triangle
// order are Draco's, not the encoded mesh's. Throws Error (input) naming `name`.
Mesh decode_draco(std::string_view bytes, const std::string& name);

// A .drc file; throws Error (input) "<path>: ...".
Mesh read_draco(const std::string& path);

} // namespace lasmesh
