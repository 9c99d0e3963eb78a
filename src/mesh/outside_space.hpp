// SPDX-License-Identifier: Apache-2.0
// The space outside every surface, as a scanner above sees it: a coarse voxel grid (at most 256
// voxels an axis, a voxel 2^k cells, one voxel of margin all round) where voxels near surface
// cells are walls, flooded from its top through the others (a breadth-first search, six
// neighbours). The inside of a closed box or of a sphere is never reached, nor the space under a
// deck or a terrain that spans the grid: their top sides are outside (and below the grid's floor
// is not, though the flood runs round under it). The sheet orients its
// pieces by it (surface_sheet.hpp). It follows from the grid's size and its surface cells alone,
// so one made from the whole grid serves a sheet of any part of it.
#pragma once

#include "lasmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace lasmesh {

class OutsideSpace {
  public:
    // `dims`: the grid's cells per axis; `surface_cells`: the grid coordinates of its surface cells.
    OutsideSpace(const std::array<std::uint32_t, 3>& dims,
                 const std::vector<std::array<std::int64_t, 3>>& surface_cells);
    // Whether the space 2.5 and 3.5 voxels from `point` (relative to the grid origin) along
    // `direction` is outside (past the walls around the point's own voxel); `cell` is the grid's.
    bool open(const std::array<double, 3>& point, const std::array<double, 3>& direction, double cell) const;
    // A voxel is 2^voxel_shift(dims) cells along each axis: at most 256 voxels an axis.
    static int voxel_shift(const std::array<std::uint32_t, 3>& dims);
    bool operator==(const OutsideSpace&) const = default;

  private:
    std::size_t index(const std::array<std::int64_t, 3>& v) const {
        return static_cast<std::size_t>((v[2] * size_[1] + v[1]) * size_[0] + v[0]);
    }
    int shift_ = 0;                      // a voxel is 2^shift cells
    std::array<std::int64_t, 3> size_{}; // voxels per axis, with one voxel of margin all round
    std::vector<char> reached_;          // per voxel, x fastest
};

// Per triangle of `mesh` (its positions relative to the grid origin): twice its area when the
// outside lies in front of it and not behind, minus that when behind and not in front, else 0. A
// piece whose triangles' votes add up below 0 faces in.
std::vector<double> outside_votes(const Mesh& mesh, const OutsideSpace& outside, double cell);

} // namespace lasmesh
