// SPDX-License-Identifier: Apache-2.0
// Mesh simplification to an error bound: edges collapse while the surface moves less than the
// bound (our own quadric edge-collapse simplifier after Garland & Heckbert 1997, see
// src/mesh/simplify.cpp), so flat areas lose most of their triangles and detail stays.
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
    double error = 0;        // the bound asked for, in the mesh's units
    double result_error = 0; // the largest bound a face of the result carries (at most `error`), same units
    double seconds = 0;
};

// Simplifies `mesh` in place, in parallel (TBB). A removed vertex moves onto a neighbour, so kept
// vertices keep their position, colour and normal (colour detail of removed vertices is lost,
// not averaged; a normal that would face away from the vertex's new faces becomes theirs, as in
// agree_normals_with_faces); vertices no longer used are removed, the rest keep their order.
// The bound holds both ways, for every point and not only the vertices: every point of the
// simplified surface lies within `error` of the original surface, and every point of the original
// within `error` of the simplified one (a bound on their Hausdorff distance; tests measure it by
// dense sampling). No face turns over against the original surface, none is left without area,
// triangles keep their winding, and no edge becomes non-manifold (borders stay borders, holes
// stay holes). Deterministic: the same bytes for any thread count.
// Vertices where a sheet touches itself, and (lock_border) all vertices on open borders, stay.
SimplifyReport simplify_mesh(Mesh& mesh, const SimplifyOptions& options);

} // namespace lasmesh
