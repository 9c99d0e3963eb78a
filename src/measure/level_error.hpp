// SPDX-License-Identifier: Apache-2.0
// How far a coarser level of detail lies from the finest one: the geometric error a 3D Tiles
// viewer weighs against the screen to choose a level.
#pragma once

#include "lasmesh/mesh.hpp"
#include "measure/mesh_distance.hpp"

#include <cstddef>
#include <vector>

namespace lasmesh {

// The finest level, searched and sampled once for all the coarser ones.
class FinestLevel {
  public:
    // `fine` must outlive this; `samples` points are spread over each surface measured.
    explicit FinestLevel(const Mesh& fine, std::size_t samples = 100000);

    // The 99th percentile of the distances from points spread over each surface (by area: a
    // small stray piece weighs what its area does, not what its vertex count does) to the other,
    // the larger of the two directions (a coarse level that rounds off a corner, or fills a gap
    // the fine level leaves, counts either way), in world units. 0 when either is empty.
    double error(const Mesh& coarse) const;

    // Removes the triangles of `coarse` whose centroid lies farther than `distance` from the
    // finest surface: what the finest level left out (an outlier cluster, removed there as a
    // small piece, that a coarse cell holds together into a larger one) is not shown at a coarser
    // level either. Returns how many; the vertices stay (a tile takes only those it uses).
    std::size_t remove_far(Mesh& coarse, double distance) const;

  private:
    const Mesh& fine_;
    std::size_t samples_;
    TriangleSearch search_;
    std::vector<Vec3> points_; // on the finest surface, in its frame
};

} // namespace lasmesh
