// SPDX-License-Identifier: Apache-2.0
// A tile job's result, as a file: the exact sums of the tile's occupied cells (whole bricks), and
// what merge needs to account for every point of the inputs the tile read. Little-endian 64-bit
// words throughout, after an 8-byte magic, and an FNV-1a hash of every byte before it at the end,
// so a file cut short or damaged in storage is told from a good one.
//
//   "LMTILE02"  plan hash, tile index, colour (0/1), largest colour word
//   device name (length, bytes)
//   inputs read: count, then per input (index in the plan, records, records outside the grid)
//   warnings: count, then per warning (input index, length, bytes)
//   bricks: count, then per brick (key, mask, first cell); cells: count, then 13 words a cell (count, position, colour,
//   moments) FNV-1a 64 of everything above
#pragma once

#include "grid/cell_sums.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace lasmesh {

struct TileInputCount {
    std::uint64_t input = 0;   // index in the plan's inputs
    std::uint64_t records = 0; // records it counts: those in its tile, and outside the grid those it read first
    std::uint64_t outside = 0; // of those, outside the grid
};

struct TileWarning {
    std::uint64_t input = 0;
    std::string text;
};

struct TileCells {
    std::uint64_t plan_hash = 0, index = 0;
    bool color = false;
    std::uint32_t color_max_word = 0;
    std::string device;
    std::vector<TileInputCount> inputs;
    std::vector<TileWarning> warnings;
    // The tile's bricks in ascending key order, as CellGrid keeps them.
    std::vector<std::uint64_t> brick_keys, brick_masks, brick_first;
    std::vector<CellSums> cells;
};

// Writes `tile` to `path` atomically (an OutputFile); throws Error (output). With `grid`, the
// bricks and cells written are the grid's (in key order, as read_tile_cells gives them), not
// tile's: a tile job writes its grid without a copy of its cells.
std::uint64_t write_tile_cells(const TileCells& tile, const std::string& path, const CellGrid* grid = nullptr);

// Reads a tile's file; throws Error (input) saying what is wrong: missing, not a tile's file,
// cut short, damaged (the hash), or holding impossible numbers.
TileCells read_tile_cells(const std::string& path);

// Reads of a tile's file only its head and the bricks `wanted` picks by key (with their cells):
// a merge's reads of a window and its halo, after read_tile_cells checked the file whole. The
// hash is not checked (it covers every byte); what is read must hold together. Throws Error
// (input) as read_tile_cells does.
TileCells read_tile_bricks(const std::string& path, const std::function<bool(std::uint64_t key)>& wanted);

} // namespace lasmesh
