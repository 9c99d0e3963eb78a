// SPDX-License-Identifier: Apache-2.0
// append_joined: the fine mesh of the thin parts joined to the coarse mesh around them where the
// two meet, on the faces of the cells where one gives way to the other.
#pragma once

#include "lasmesh/grid.hpp"
#include "lasmesh/mesh.hpp"

#include <cstdint>
#include <vector>

namespace lasmesh {

// How the seam between the two meshes went: the cell faces that hold a border of both meshes,
// the stretches of fine border joined to the coarse border, and the length of the two meshes'
// borders on the seam's faces before and after (in the positions' units).
struct SeamReport {
    std::size_t faces = 0;
    std::size_t joined = 0;
    double open_before = 0, open_after = 0;
};

// Appends `thin` to `coarse` (as append_mesh) and joins them along the seam. `coarse` holds only
// triangles in cells of `grid` not in `fine_cells` (cell keys, ascending, as
// thin_parts.hpp's blocks_around numbers them at shift 0), `thin` only triangles in those cells,
// marched on the lattice of half the cell on the same origin: both end on the faces between the
// two kinds of cells, with their own vertices. First each connected part of `thin` is turned to
// face the way the coarse mesh does where they meet (the two were oriented each on its own).
// Then each mesh's border on the seam is followed from face to face, and the fine border laid
// onto the coarse one where the two run side by side, at most half a cell apart, the opposite
// way round (both surfaces facing one side), whichever faces they cross: each coarse vertex the
// stretch passes takes the nearer fine vertex, the others go onto the coarse edges, which are
// split at them, so the two meshes share the seam's edges (the crack patching of Shu, Zhou &
// Kankanhalli 1995, "Adaptive marching cubes", carried across faces as Turk & Levoy 1994's
// zippering clips one border to the other). Elsewhere (a plate's back face or a tube's ring
// meeting the coarse sheet, a hole, a move that would turn a fine triangle over or give an edge
// a third triangle) the borders stay as they were.
SeamReport append_joined(Mesh& coarse, const Mesh& thin, const GridSpec& grid,
                         const std::vector<std::uint64_t>& fine_cells);

} // namespace lasmesh
