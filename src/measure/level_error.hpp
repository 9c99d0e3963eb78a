// SPDX-License-Identifier: Apache-2.0
// How far a coarser level of detail lies from the finest one: the geometric error a 3D Tiles
// viewer weighs against the screen to choose a level.
#pragma once

#include "lasmesh/mesh.hpp"

namespace lasmesh {

// The 99th percentile of the distances from points spread over each mesh's surface (by area) to
// the other's, the larger of the two directions (a coarse level that rounds off a corner, or
// fills a gap the fine level leaves, counts either way), in world units; `samples` points on
// each. 0 when either mesh is empty.
double level_error(const Mesh& coarse, const Mesh& fine, std::size_t samples = 100000);

// Removes the triangles of `coarse` whose centroid lies farther than `distance` from `fine`'s
// surface: what the finest level left out (an outlier cluster, removed there as a small piece,
// that a coarse cell holds together into a larger one) is not shown at a coarser level either.
// Returns how many were removed; the vertices stay (a tile takes only those it uses).
std::size_t remove_far_from(Mesh& coarse, const Mesh& fine, double distance);

} // namespace lasmesh
