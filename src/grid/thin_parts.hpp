// SPDX-License-Identifier: Apache-2.0
// Where the surface is thinner than a cell in two directions (a rail, a post, a cable): there the
// sheet has no plane to follow and meshes a tube a cell wide, so those parts are meshed again at
// half the cell (build_mesh.cpp, BuildOptions::refine_thin).
#pragma once

#include "grid/cell_sums.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace lasmesh {

// A surface cell's part is thin when the count-weighted centroids of the surface cells around
// it (3 x 3 x 3, at least 3 of them) spread along a line: the middle eigenvalue of their
// covariance under this share of the largest. On a plane (a deck, a wall, a pipe wider than a
// few cells) the two largest are alike; a plane's edge gives a quarter to a half, and less where
// the plane ends in a sliver of a cell: there the plane beside the line tells it apart.
constexpr double thin_line_ratio = 0.2;

// By default thin parts are refined when the automatic grid's occupied cells hold a median of at
// least this many points: a surface cell of half the size holds about a quarter of them, and a
// plane or a tube through a cell's points needs 3. (The corpus's aerial files, which fit worse
// refined, hold 1-11; the generated deck at 20M and 181M points 15 and 117, at 2M 7.)
constexpr std::uint64_t thin_parts_min_median = 12;

// The finer mesh replaces the coarse one in the cells within this many cells of a thin cell:
// the coarse sheet's tube around a thin part reaches a cell past it (measured on the deck: kept
// to the thin cells alone, the railings stay 4.8 cm off their truth; one cell past, 1.5 cm).
constexpr std::int64_t thin_mesh_reach = 1;
// The points of the cells within this many cells of a thin cell are read again: one past those
// meshed fine, so that every fine cell whose vertex or edges a kept triangle uses has all its
// points (and its neighbours theirs).
constexpr std::int64_t thin_read_reach = 2;

// The thin surface cells (count above `iso`) of `grid`, and the surface cells between them (thin
// cells on opposite sides within two cells: a rail's junction with a post, a gap along a rail),
// z slowest then y then x. A plane's edge is not thin: refined, its seam with the coarse mesh
// would run along the plane, where the two sheets' borders wander apart and stay open.
std::vector<std::array<std::int64_t, 3>> thin_cells(const CellGrid& grid, double iso);

// The keys ((z * count[1] + y) * count[0] + x, ascending) of the blocks of 2^shift cells an edge
// that hold one of `cells`, and of those within `reach` blocks of them, occupied or not, inside
// `count` blocks an axis. Shift 0: cells; CellGrid::brick_bits: bricks.
std::vector<std::uint64_t> blocks_around(const std::vector<std::array<std::int64_t, 3>>& cells,
                                         const std::array<std::int64_t, 3>& count, int shift, std::int64_t reach);

// The eigenvalues of a symmetric 3 x 3 matrix, largest first (the trigonometric solution of the
// characteristic cubic, Smith 1961).
std::array<double, 3> symmetric_eigenvalues(const std::array<std::array<double, 3>, 3>& a);

} // namespace lasmesh
