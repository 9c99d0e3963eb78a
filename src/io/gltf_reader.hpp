// SPDX-License-Identifier: Apache-2.0
// Reading back the .glb files lasmesh writes, plain or Draco-compressed, into a Mesh in the file's
// local frame: for the tests and for `lasmesh compare`.
//
//     lasmesh::Mesh mesh = lasmesh::read_glb("deck.glb"); // throws lasmesh::Error (input)
#pragma once

#include "lasmesh/mesh.hpp"

#include <string>

namespace lasmesh {

// A .glb as write_glb writes it: the first mesh's first primitive, plain or Draco-compressed (its
// attributes found by the unique ids the KHR_draco_mesh_compression extension names), and the origin from the node's
// extras, else its translation (undoing the Z-up to Y-up rotation). Throws Error (input) "<path>: ...".
Mesh read_glb(const std::string& path);

} // namespace lasmesh
