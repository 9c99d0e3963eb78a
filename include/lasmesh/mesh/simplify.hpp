// Mesh simplification to an error bound: edges collapse while the surface moves less than the
// bound (meshoptimizer's quadric simplifier), so flat areas lose most of their triangles and
// detail stays.
#pragma once

#include "lasmesh/mesh.hpp"

#include <cstddef>

namespace lasmesh {

struct SimplifyOptions {
    double error = 0;         // the largest distance the surface may move, in the mesh's units; 0: off
    bool lock_border = false; // vertices on open borders never move (tile seams)
};

struct SimplifyReport {
    std::size_t triangles_before = 0, triangles_after = 0;
    double error = 0;         // the bound asked for, in the mesh's units
    double result_error = 0;  // meshoptimizer's estimate of the error reached, same units
    double seconds = 0;
    std::size_t redone_blocks = 0;        // blocks simplified again with a smaller bound (a face turned over)
    std::size_t unsimplified_blocks = 0;  // blocks left as they were (no bound small enough helped)
};

// Simplifies `mesh` in place. Kept vertices keep their position, colour and normal (colour
// detail of removed vertices is lost, not averaged); vertices no longer used are removed, the
// rest keep their relative order. Triangles keep their winding; the topology is preserved (no
// new non-manifold edges, no holes). Deterministic: same mesh, same result, whatever the threads.
SimplifyReport simplify_mesh(Mesh& mesh, const SimplifyOptions& options);

// What a simplification did to the surface, for tests and benchmarks. Vertices of `simplified`
// are matched to those of `original` by position (simplification keeps the vertices it keeps
// where they are).
struct SimplifyCheck {
    // Faces whose normal points against the original surface at their corners: against the sum
    // of the original area-weighted vertex normals of their three vertices. Faces that are in
    // the original as they are do not count (the extraction folds a few faces itself).
    std::size_t flipped = 0;
    std::size_t unmatched_vertices = 0;            // vertices at no original vertex's position
    std::size_t bad_edges = 0, bad_edges_before = 0; // used by 3+ faces, or twice in one direction
    std::size_t zero_area = 0, zero_area_before = 0; // faces with (next to) no area
};
SimplifyCheck check_simplified(const Mesh& original, const Mesh& simplified);

} // namespace lasmesh
