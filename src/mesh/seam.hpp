// SPDX-License-Identifier: Apache-2.0
// append_joined: the fine mesh of the thin parts joined to the coarse mesh around them where the
// two meet, on the faces of the cells where one gives way to the other.
#pragma once

#include "lasmesh/grid.hpp"
#include "lasmesh/mesh.hpp"

#include <cstdint>
#include <vector>

namespace lasmesh {

// How the seam between the two meshes went: the cell faces where a border of the coarse mesh
// and a border of the fine one lie, and the chains of fine edges joined to a coarse segment there.
struct SeamReport {
    std::size_t faces = 0;
    std::size_t joined = 0;
};

// Appends `thin` to `coarse` (as append_mesh) and joins them along the seam. `coarse` holds only
// triangles in cells of `grid` not in `fine_cells` (cell keys, ascending, as
// thin_parts.hpp's blocks_around numbers them at shift 0), `thin` only triangles in those cells,
// marched on the lattice of half the cell on the same origin: both end on the faces between the
// two kinds of cells, with their own vertices. First each connected part of `thin` is turned to
// face the way the coarse mesh does where they meet (the two were oriented each on its own). On
// each face of the seam the coarse mesh's border is a segment from a cell edge to another, the
// thin one's a chain across the face; where they agree (the chain runs between the segment's two
// cell edges, the opposite way round), the chain's ends become the segment's ends, its inner
// vertices move onto the segment, and the coarse triangle is split at them, so the two meshes
// share the seam's edges (after the crack patching of Shu, Zhou & Kankanhalli 1995, "Adaptive
// marching cubes"). A chain with one end on one of the segment's cell edges (the other inside the
// face, at a hole of the fine sheet, or on another cell edge) is laid from that end as far as it
// follows the segment. Elsewhere (no counterpart, a move that would turn a fine triangle over) the
// borders stay as they were.
SeamReport append_joined(Mesh& coarse, const Mesh& thin, const GridSpec& grid,
                         const std::vector<std::uint64_t>& fine_cells);

} // namespace lasmesh
