// SPDX-License-Identifier: Apache-2.0
// What the mesh readers share: a whole file in memory, and a Draco stream decoded with its
// attributes chosen by unique id (as a .glb's KHR_draco_mesh_compression names them).
#pragma once

#include "lasmesh/mesh.hpp"

#include <optional>
#include <string>
#include <string_view>

namespace lasmesh {

// The bytes of `path`; throws Error (input) "<path>: cannot open" or "read failed".
std::string read_whole_file(const std::string& path);

// Throws Error (input) naming `name` when the stream is not a Draco mesh or lacks the attributes.
Mesh decode_draco_attributes(std::string_view bytes, const std::string& name, int position_id,
                             std::optional<int> color_id, std::optional<int> normal_id);

} // namespace lasmesh
