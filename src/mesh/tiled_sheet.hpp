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
#include "mesh/seam_corners.hpp"
#include "mesh/surface_sheet.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace lasmesh {

// The tiles' windows of a grid, [x0, x1) and [y0, y1) in its cells, row by row (y, then x).
std::vector<std::array<std::int64_t, 4>> tile_windows(const GridSpec& grid, std::int64_t tile_cells);

// A tile's part of the grid: its cells and a halo's round them, in the grid's frame
// (bricks_within of a grid held whole, or a tile's cells and its neighbours' read from their files).
using TilePart = std::function<CellGrid(const std::array<std::int64_t, 4>& window)>;

// The tiles' first look, before any sheet is made: the survey they make together, and the thin
// cells (grid/thin_parts.hpp) each finds in its window, listed as thin_cells lists the whole
// grid's (z slowest, then y, then x). A halo of 4 cells or more gives the whole grid's thin cells.
struct TiledSurvey {
    SheetSurvey survey;
    std::vector<std::array<std::int64_t, 3>> thin; // only when asked for
};
TiledSurvey survey_tiles(const GridSpec& grid, const std::vector<std::array<std::int64_t, 4>>& windows,
                         const TilePart& part_of, double iso, bool thin);

// The thin cells of `part` (thin_cells) that lie in `window`.
std::vector<std::array<std::int64_t, 3>> tile_thin_cells(const CellGrid& part, double iso,
                                                         const std::array<std::int64_t, 4>& window);

// One tile's sheet: `part` holds the tile's cells and its halo's (in the grid's frame), and the
// triangles whose centroid lies in `window` are kept. With `seam` (seam_corners_of, its samples
// sized to its corners), the tile samples the seam's corners in and on its window and writes
// those it owns (x in [window[0], window[1]), y likewise; the grid's last corners to its last
// tiles) into `seam`: every tile of the grid so, the seam is sampled as the whole grid's sheet
// samples it (but for the sign of a corner whose tile faces the other way: SeamFaces signs each
// corner the way the fine sheet faces).
Mesh tile_sheet(const CellGrid& part, double iso, const SheetSurvey& survey, const std::array<std::int64_t, 4>& window,
                SeamCorners* seam = nullptr);

// Every tile's sheet (tile_sheet), their regions turned to face as one (tile_facing.hpp) and
// their meshes joined; `seam`, when given, sampled by the tiles.
Mesh sheets_of_tiles(const GridSpec& grid, const std::vector<std::array<std::int64_t, 4>>& windows,
                     const TilePart& part_of, double iso, const SheetSurvey& survey, SeamCorners* seam = nullptr);

// survey_tiles, then sheets_of_tiles, the parts cut from a grid held whole.
Mesh extract_sheet_in_tiles(const CellGrid& grid, double iso, std::int64_t tile_cells, std::int64_t halo);

} // namespace lasmesh
