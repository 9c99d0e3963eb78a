// SPDX-License-Identifier: Apache-2.0
// Extraction: the iso-surface of the grid of point counts by marching cubes, in parallel with oneTBB
// and with the same output for any number of threads.
#pragma once

#include "grid/cell_sums.hpp"
#include "lasmesh/mesh.hpp"
#include "lasmesh/surface.hpp"

#include <string>

namespace lasmesh {

// The iso value when none is given: a tenth of the median count of the occupied cells, at least
// 1. Cells along a surface hold roughly density x cell area points, so this follows the scan's
// density: sparse parts still close while stray single points stay outside.
double automatic_iso(const CellGrid& grid);
// The same from the median, counted already (a merge counts it from its tiles).
double automatic_iso(std::uint64_t median_count);

// The surface between cells with count > iso (inside) and the others. The samples are the cell
// centres; the grid is padded with one layer of empty cells, so every surface closes. One
// vertex per crossed lattice edge, shared by every triangle that uses it, placed strictly
// inside the edge by `placement` (for `iso`, an integer iso is interpolated at iso + 0.5).
// Colour: the two cells' mean colours weighted by their counts and the interpolation weights.
// Triangles wind counter-clockwise seen from outside (normals point from dense to empty).
// The mesh's origin is the grid origin.
Mesh extract_closed_surface(const CellGrid& grid, double iso, VertexPlacement placement = VertexPlacement::surface);

} // namespace lasmesh
