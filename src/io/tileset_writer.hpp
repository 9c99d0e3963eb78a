// SPDX-License-Identifier: Apache-2.0
// An OGC 3D Tiles 1.1 tileset: levels of detail of one surface, each cut into the tiles of one
// global lattice (a quadtree in x and y: a tile of level k holds the 2 x 2 tiles of level k + 1
// below it), each tile a glTF binary, refined by replacement.
//
//   NAME.json              asset 1.1, the tree, each tile's box, geometric error and content
//   NAME-<hash>/K/X_Y.glb  the tile X, Y of level K (0: the root, coarsest)
//
// The contents' folder is named after a hash of their bytes: it is written under a temporary
// name, renamed when complete, and NAME.json (committed with the run's other outputs) names it,
// so a reader never sees a tileset with missing tiles; the folders of earlier runs are removed
// once the new NAME.json is in place.
//
// With a coordinate system the tileset is placed on the globe: the root's transform is an
// east-north-up frame at the data's centre (io/globe_frame.hpp) and the tiles' positions are
// carried into it by PROJ. Without one the tiles are in the data's units around its centre,
// which `extras` gives, and the tileset is not placed.
#pragma once

#include "io/gltf_writer.hpp"
#include "io/output_file.hpp"
#include "lasmesh/mesh.hpp"
#include "read/crs.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lasmesh {

struct TilesetLevel {
    const Mesh* mesh = nullptr; // the level's whole surface, in the survey's CRS (world = origin + position)
    double error = 0;           // its distance to the finest level, in the CRS's unit (0 for the finest)
};

struct TilesetLattice {
    Vec3 corner{};        // where tile (0, 0) of every level starts (world x, y)
    double root_edge = 0; // the root level's tile edge; level k's is root_edge / 2^k
};

struct TilesetContent {
    GltfOptions glb;            // the contents' compression
    std::optional<CrsInfo> crs; // identified: the tileset is placed on the globe
};

struct WrittenTileset {
    std::string folder;                        // the contents' folder, beside NAME.json
    std::vector<std::size_t> tiles, triangles; // per level
    std::vector<double> geometric_error;       // per level, in metres (or the data's unit)
    std::uint64_t content_bytes = 0;
    bool folder_created = false; // false: the same contents were there from an earlier run
    std::string note;            // why the tileset is not on the globe; empty when it is
};

// Writes the contents into place and NAME.json into `json` (not yet committed). `levels` are
// coarsest first. Throws Error (output) when a file cannot be written, (input) when PROJ cannot
// place the data.
WrittenTileset write_tileset(const std::vector<TilesetLevel>& levels, const TilesetLattice& lattice,
                             const TilesetContent& content, OutputFile& json);

// After NAME.json is committed: the contents' folders of earlier runs, beside it, removed.
void remove_earlier_tiles(const std::string& json_path, const std::string& kept_folder);

} // namespace lasmesh
