// SPDX-License-Identifier: Apache-2.0
// A grid's sheet meshed tile by tile.
//
//     const Mesh sheet = extract_sheet_in_tiles(grid, automatic_iso(grid), 64, 8);
//
// Each tile (tile_cells x tile_cells cells in x and y, all of z) is meshed from its own cells
// and a halo round them (bricks_within), with the survey the tiles make together
// (sheet_survey_part, combined_survey: surface_sheet.hpp), and keeps the triangles whose centroid
// lies in it; the tiles' regions are turned to face as one (tile_facing.hpp) and their meshes
// joined where their vertices coincide (a halo of 8 cells or more gives two tiles the same
// vertices along their shared border, bit for bit). Each step looks at one tile, or at what the
// tiles hand on (their survey parts and their regions), never at the whole grid: the steps a
// cluster's tile jobs can take each on its own machine, here taken in turn on one.
#pragma once

#include "grid/cell_sums.hpp"
#include "lasmesh/mesh.hpp"
#include "mesh/surface_sheet.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace lasmesh {

// The tiles' windows of a grid, [x0, x1) and [y0, y1) in its cells, row by row (y, then x).
std::vector<std::array<std::int64_t, 4>> tile_windows(const GridSpec& grid, std::int64_t tile_cells);

// One tile's sheet: `part` holds the tile's cells and its halo's (in the grid's frame), and the
// triangles whose centroid lies in `window` are kept.
Mesh tile_sheet(const CellGrid& part, double iso, const SheetSurvey& survey, const std::array<std::int64_t, 4>& window);

Mesh extract_sheet_in_tiles(const CellGrid& grid, double iso, std::int64_t tile_cells, std::int64_t halo);

} // namespace lasmesh
