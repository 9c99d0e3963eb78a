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
// few cells) the two largest are alike; a plane's edge gives a quarter to a half.
constexpr double thin_line_ratio = 0.2;

// The keys of the bricks (grid.brick_keys' numbering) that hold a thin surface cell (count above
// `iso`), and of the bricks around them, occupied or not (26 neighbours: the finer mesh's seam
// with the rest lies a brick away from the thin part, and a sheet reaches past the points),
// ascending.
std::vector<std::uint64_t> thin_bricks(const CellGrid& grid, double iso);

// The eigenvalues of a symmetric 3 x 3 matrix, largest first (the trigonometric solution of the
// characteristic cubic, Smith 1961).
std::array<double, 3> symmetric_eigenvalues(const std::array<std::array<double, 3>, 3>& a);

} // namespace lasmesh
