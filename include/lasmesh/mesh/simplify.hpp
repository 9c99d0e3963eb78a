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
};

// Simplifies `mesh` in place. Kept vertices keep their position, colour and normal (colour
// detail of removed vertices is lost, not averaged); vertices no longer used are removed, the
// rest keep their relative order. Triangles keep their winding; the topology is preserved (no
// new non-manifold edges, no holes). Deterministic: same mesh, same result, whatever the threads.
SimplifyReport simplify_mesh(Mesh& mesh, const SimplifyOptions& options);

} // namespace lasmesh
