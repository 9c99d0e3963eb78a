// SPDX-License-Identifier: Apache-2.0
// A grid's sheet meshed tile by tile.
//
//     const Mesh sheet = extract_sheet_in_tiles(grid, automatic_iso(grid), 64, 8);
//
// Each tile (tile_cells x tile_cells cells in x and y, all of z) is meshed from its own cells
// and a halo round them (bricks_within), and keeps the triangles whose centroid lies in it. Three
// things are decided from what the tiles hand on, each small beside their cells: the survey
// (the scan's noise and the outside: sheet_survey_part, combined_survey), which way the planes
// face (unfaced_planes, plane_facing: surface_sheet.hpp) and which connected parts turn to face
// the outside (tile_facing.hpp). The meshes are joined where their vertices coincide (a halo of 8
// cells or more gives two tiles the same vertices along their shared border, bit for bit): the
// whole grid's sheet, triangle for triangle. Each step looks at one tile, or at what the tiles
// hand on, never at the grid's cells as one: the steps a cluster's tile jobs can take each on its
// own machine, here taken in turn on one.
#pragma once

#include "grid/cell_sums.hpp"
#include "lasmesh/mesh.hpp"
#include "mesh/seam_corners.hpp"
#include "mesh/surface_sheet.hpp"
#include "mesh/tile_facing.hpp"

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

// The tiles' planes faced as the whole grid's (unfaced_planes of each tile, plane_facing).
PlaneFacing face_tiles(const GridSpec& grid, const std::vector<std::array<std::int64_t, 4>>& windows,
                       const TilePart& part_of, double iso, const SheetSurvey& survey);

// One tile's sheet before step 5: `part` holds the tile's cells and its halo's (in the grid's
// frame), its planes faced as `facing` says, marched (faced_sheet), with what outside_turns needs
// of it (tile_facing.hpp). With `seam` (seam_corners_of, its samples sized to its corners), the
// tile samples the seam's corners in and on its window and writes those it owns (x in
// [window[0], window[1]), y likewise; the grid's last corners to its last tiles) into `seam`:
// every tile of the grid so, the seam is sampled as the whole grid's sheet samples it.
struct TileSheet {
    FacedSheet faced;
    TileParts parts;
};
TileSheet tile_sheet(const CellGrid& part, double iso, const SheetSurvey& survey, const PlaneFacing& facing,
                     const std::array<std::int64_t, 4>& window, SeamCorners* seam = nullptr);
// The tile's share of the sheet once its parts' turns are known (outside_turns): turned, plates
// split into their faces, and the triangles whose centroid lies in `window` kept.
Mesh finish_tile_sheet(TileSheet&& sheet, const std::vector<char>& turns, const std::array<std::int64_t, 4>& window);

// Every tile's sheet, faced as one (face_tiles, tile_sheet, outside_turns, finish_tile_sheet), and
// their meshes joined where their vertices coincide; `seam`, when given, sampled by the tiles.
// The whole grid's sheet, triangle for triangle, with a halo of 8 cells or more.
Mesh sheets_of_tiles(const GridSpec& grid, const std::vector<std::array<std::int64_t, 4>>& windows,
                     const TilePart& part_of, double iso, const SheetSurvey& survey, SeamCorners* seam = nullptr);

// The whole grid's sheet in the order sheets_of_tiles gives it: its triangles tile by tile (by
// their centroid, as the tiles keep them; within a tile in their order), its vertices numbered
// by first use (those of one place and one normal made one, as the tiles' are where they meet).
// The tiles' sheet and the whole grid's are then the same mesh, array for array, so what follows
// them (simplification, writers) gives the same bytes.
Mesh in_tile_order(Mesh&& sheet, const GridSpec& grid, std::int64_t tile_cells);

// survey_tiles, then sheets_of_tiles, the parts cut from a grid held whole.
Mesh extract_sheet_in_tiles(const CellGrid& grid, double iso, std::int64_t tile_cells, std::int64_t halo);

} // namespace lasmesh
