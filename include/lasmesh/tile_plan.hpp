// SPDX-License-Identifier: Apache-2.0
// A survey too large for one machine's time, read on many: a plan fixes the grid from the
// inputs' headers and cuts it into tiles; each tile job (one task of a Slurm array or a
// Kubernetes Indexed Job) reads only the inputs that touch its tile and writes the exact sums of
// its tile's cells; merge adds them into the grid one machine would have accumulated and
// meshes it: every output is byte for byte the one build_mesh writes from the same inputs.
//
//     lasmesh::BuildOptions options;                       // the grid, bounds and CRS to plan with
//     lasmesh::TilePlan plan = lasmesh::plan_tiles(inputs, options, 250.0);   // headers only
//     lasmesh::write_plan(plan, "site.plan.json");
//     // on each node, K from 0 to plan.tiles.size() - 1:
//     lasmesh::run_tile(lasmesh::read_plan("site.plan.json"), K, options);
//     // once every tile is done, with the outputs and meshing options in `options`:
//     options.outputs.push_back({"site/tileset.json"});
//     lasmesh::merge_tiles(lasmesh::read_plan("site.plan.json"), options);
//
// Files: the plan names its tiles' folder, "<plan without .json>-tiles/" beside it, where tile
// K writes "tile-K.cells" (atomically: a rerun replaces it). Inputs and outputs are paths on a
// file system every node sees (a cluster's shared storage).
#pragma once

#include "lasmesh/build_mesh.hpp"
#include "lasmesh/grid.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lasmesh {

struct PlannedInput {
    std::string path;         // absolute: tile jobs may start in another folder
    std::uint64_t bytes = 0;  // its size, and its header's point count, when planned: a tile job
    std::uint64_t points = 0; // refuses an input that has changed since
};

// A tile: the grid's cells [x_cells[0], x_cells[1]) x [y_cells[0], y_cells[1]), all of z.
struct PlannedTile {
    std::uint32_t x = 0, y = 0; // its place in the tiling
    std::array<std::uint32_t, 2> x_cells{}, y_cells{};
    std::vector<std::size_t> inputs; // indices into TilePlan::inputs: those whose header bounds touch it
    std::uint64_t points = 0;        // the points those inputs' headers promise (they may hold more)
};

struct TilePlan {
    std::string path;       // the plan's file (read_plan's or write_plan's): the tiles' folder is beside it
    std::uint64_t hash = 0; // of the plan's file: a tile's sums name the plan they belong to
    std::vector<PlannedInput> inputs;
    GridRequest grid_request;       // as asked (automatic: coarsened from the counts when merged)
    std::optional<Bounds> bounds;   // as asked
    std::string crs;                // as asked (empty: the inputs')
    GridSpec grid;                  // the grid every tile accumulates into (automatic: before coarsening)
    std::string unit;               // the CRS's unit of length; empty without a CRS
    double tile_size = 0;           // a tile's edge in x and y, in the CRS's unit (tile_cells cells)
    std::uint32_t tile_cells = 0;   // a multiple of 4 (the grid's bricks)
    std::vector<PlannedTile> tiles; // those that touch an input, by y then x
};

// Reads the inputs' headers only and fixes the grid and the tiles. `tile_size` in the CRS's unit
// (rounded up to whole bricks of 4 cells); 0: about 20 million promised points a tile. Only the
// read options of `options` count (grid, bounds, crs); scan_bounds and skip_bad_inputs are
// refused (Error usage): a tile job must read exactly the files planned. Throws Error (input)
// naming an input that cannot be read.
TilePlan plan_tiles(const std::vector<std::string>& inputs, const BuildOptions& options, double tile_size);

// The plan as JSON in `path` (atomically), and read back; read_plan throws Error (input) naming
// what is wrong with the file.
void write_plan(TilePlan& plan, const std::string& path);
TilePlan read_plan(const std::string& path);
// The folder of a plan's tiles, and tile K's file in it.
std::string tiles_folder(const TilePlan& plan);
std::string tile_path(const TilePlan& plan, std::size_t index);

struct TileReport {
    std::size_t index = 0;
    std::string path;                 // the tile's cell sums, written
    std::uint64_t inputs_read = 0;    // the inputs whose headers touch the tile
    std::uint64_t points_read = 0;    // their points
    std::uint64_t points_in_tile = 0; // of those, the points in the tile's cells
    std::uint64_t occupied_cells = 0; // the tile's
    std::uint64_t bytes = 0;          // of its file
    double seconds = 0;
    std::uint64_t peak_rss_bytes = 0;
};

// Reads the inputs of tile `index` and writes its cells' sums. Of `options`, the device, slice
// and memory fields count. Throws Error (usage) for an index past the plan's tiles, (input) for
// an input changed since the plan, or holding a point outside its header's bounds in a tile that
// does not read it (its points would be lost: the message names the file, the record and the tile).
TileReport run_tile(const TilePlan& plan, std::size_t index, const BuildOptions& options,
                    BuildObserver* observer = nullptr);

// Adds the tiles' sums into the grid and meshes it into options.outputs, as build_mesh(inputs,
// options) would with the plan's grid, bounds and CRS (the read fields of `options` are not
// used). Throws Error (input) listing every tile missing, damaged or from another plan, before
// reading any.
BuildResult merge_tiles(const TilePlan& plan, const BuildOptions& options, BuildObserver* observer = nullptr);

} // namespace lasmesh
