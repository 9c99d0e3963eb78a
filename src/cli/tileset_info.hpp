// SPDX-License-Identifier: Apache-2.0
// `lasmesh info TILESET.json`: a 3D Tiles tileset's levels (depths of its tree): tiles, contents,
// triangles and bytes of the .glb contents, geometric errors; whether it is placed on the globe.
// Any 3D Tiles 1.0/1.1 tileset.json, not only lasmesh's: triangles are counted from the .glb
// files themselves (their index accessors), bytes from the files.
#pragma once

#include <ostream>
#include <string>

namespace lasmesh::cli {

// A path `lasmesh info` shows as a tileset: it ends in .json.
bool is_tileset_path(const std::string& path);

// Throws lasmesh::Error (input) naming the file when it is not a tileset's JSON.
void write_tileset_info(const std::string& path, bool json, std::ostream& out);

} // namespace lasmesh::cli
