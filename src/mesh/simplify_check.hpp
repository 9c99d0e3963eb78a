// SPDX-License-Identifier: Apache-2.0
// Checks of a simplification's result against the mesh it started from, for the tests and the
// benchmarks.
#pragma once

#include "lasmesh/mesh.hpp"

#include <cstddef>

namespace lasmesh {

// What a simplification did to the surface, for tests and benchmarks. Vertices of `simplified`
// are matched to those of `original` by position (simplification keeps the vertices it keeps
// where they are).
struct SimplifyCheck {
    // Faces whose normal points against the original surface at their corners: against the sum
    // of the original area-weighted vertex normals of their three vertices. Faces that are in
    // the original as they are do not count (the extraction folds a few faces itself).
    std::size_t flipped = 0;
    std::size_t unmatched_vertices = 0;              // vertices at no original vertex's position
    std::size_t bad_edges = 0, bad_edges_before = 0; // used by 3+ faces, or twice in one direction
    std::size_t zero_area = 0, zero_area_before = 0; // faces with (next to) no area
};
SimplifyCheck check_simplified(const Mesh& original, const Mesh& simplified);

} // namespace lasmesh
