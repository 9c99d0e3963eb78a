// SPDX-License-Identifier: Apache-2.0
// Extraction: the iso-surface of the density grid by marching cubes, in parallel with oneTBB
// and with the same output for any number of threads.
#pragma once

#include "lasmesh/grid/density_grid.hpp"
#include "lasmesh/mesh.hpp"

#include <string>

namespace lasmesh {

// The iso value for `--iso auto`: a tenth of the median count of the occupied cells, at least
// 1. Cells along a surface hold roughly density x cell area points, so this follows the scan's
// density: sparse parts still close while stray single points stay outside.
double automatic_iso(const DensityGrid& grid);

// Where a vertex goes along its crossed edge.
enum class VertexPlacement {
    // At half the local layer's count (see edge_fraction in marching_cubes.cpp): on the scanned
    // surface rather than around it. Scans put points on surfaces, so the occupied cells form a
    // thin layer that a plain level set wraps at up to a cell on each side.
    surface,
    // Classic marching cubes: linear interpolation of the counts at the iso value.
    iso,
};

// The surface between cells with count > iso (inside) and the others. The samples are the cell
// centres; the grid is padded with one layer of empty cells, so every surface closes. One
// vertex per crossed lattice edge, shared by every triangle that uses it, placed strictly
// inside the edge by `placement` (for `iso`, an integer iso is interpolated at iso + 0.5).
// Colour: the two cells' mean colours weighted by their counts and the interpolation weights.
// Triangles wind counter-clockwise seen from outside (normals point from dense to empty).
// The mesh's origin is the grid origin.
Mesh extract_isosurface(const DensityGrid& grid, double iso, VertexPlacement placement = VertexPlacement::surface);

} // namespace lasmesh
