// SPDX-License-Identifier: Apache-2.0
// A grid chosen from the data: a cell size from the data's density, so that the cells on a scanned surface hold
// enough points for the surface to close. Too fine a grid leaves holes (cells with no points
// between the points); too coarse a one blurs detail. Estimated from the header alone (count and
// extents), before any point is read; then, once the points are counted, coarsened while most
// occupied cells hold too few points (the header cannot tell a surface's true area).
#pragma once

#include "grid/cell_sums.hpp"
#include "lasmesh/grid.hpp"
#include "read/las_header.hpp"

#include <cstdint>
#include <string>

namespace lasmesh {

struct GridChoice {
    GridRequest request;        // cells along the longest axis
    std::string reason;         // for the summary: "the points cover about 120 m2, ...: 180 cells"
    double points_per_cell{};   // aimed at (auto_grid_points_per_cell)
    std::uint64_t min_median{}; // the second look coarsens while the occupied cells' median is below this
};

// Points per surface cell aimed at: 12 on large inputs, so that a scan's noise is averaged out
// and the mesh stays small; a small input is cheap to mesh at any cell, so it gets cells for about
// auto_grid_detail_cells surface cells, down to 3.5 points a cell. Measured (docs/benchmarks.md,
// "Sparse data"): the generated deck at 300,000 points is best at 4 a cell (at 3 its deck opens
// into holes), autzen-thin's aerial points at 3; 3.5 is within 2% and 10% of either's best.
constexpr double auto_grid_most_points_per_cell = 12, auto_grid_fewest_points_per_cell = 3.5;
constexpr double auto_grid_detail_cells = 100'000;
// clamp(point_count / auto_grid_detail_cells, fewest, most).
double auto_grid_points_per_cell(std::uint64_t point_count);
// The cells along the longest axis allowed.
constexpr std::uint32_t auto_grid_min_cells = 16, auto_grid_max_cells = 1024;
// Fewer points than this cannot outline a closed surface at the coarsest grid.
constexpr std::uint64_t auto_grid_min_points = 100;

// The grid for `point_count` points in `bounds`, auto_grid_points_per_cell in a surface cell, assuming they lie on a
// surface whose area is about the sum of the two largest face areas of the bounding box (a terrain, a facade, a hull
// seen from around). Throws Error (input) when there are too few points for any surface, naming the option to give
// instead.
GridChoice choose_grid(std::uint64_t point_count, const Bounds& bounds, const std::string& input_name);

// After accumulating: the grid is coarsened (cells merged 2 x 2 x 2) while the median count of
// the occupied cells is below a third of the points a cell aimed at (4 for 12), at least 2, and the
// longest axis has more than auto_grid_min_cells.
std::uint64_t auto_grid_min_median(double points_per_cell);

// The automatic grid's second look: coarsens `grid` while the median count of its occupied cells is
// below `min_median` and its longest axis has more than auto_grid_min_cells. Returns what was
// done, for the summary ("" when nothing).
std::string coarsen_while_sparse(CellGrid& grid, std::uint64_t min_median);

// The automatic grid's second look at a grid accumulated as `choice` asked: coarsen_while_sparse,
// and grid_reason says why it is this grid ("auto: ...").
void finish_chosen_grid(CellGrid& grid, const GridChoice& choice);

// Any grid, asked for or chosen, is the finest the mesh uses, not a promise to mesh at it: while
// more than half of its occupied cells hold a single point (the median count is 1), no surface
// goes through most of the points (a lone point has no plane, and the surface cells hold more
// than the iso, at least 1, of them), so the grid is coarsened (2 x 2 x 2 cells merged, exactly)
// while that holds and its longest axis has more than auto_grid_min_cells. Returns how many
// times it was coarsened.
int coarsen_while_single_points(CellGrid& grid);

// The grid with cells twice as large: each cell the exact sums of the 2 x 2 x 2 cells it covers
// (the last cell along an odd axis covers one and ends where the fine grid ended). Otherwise
// the grid accumulating at that cell size gives.
CellGrid coarsen_grid(const CellGrid& fine);

// The grid whose parts `parts` are (each with the grid's frame, its bricks in ascending key
// order), the cells two parts both hold summed: a merge coarsens its tiles one at a time
// (coarsen_grid of each) and sums them into the coarse grid coarsen_grid makes of the whole
// (its sums are integers, exact in any order). Points read and outside are left at 0.
CellGrid sum_of_parts(std::vector<CellGrid>&& parts);

} // namespace lasmesh
