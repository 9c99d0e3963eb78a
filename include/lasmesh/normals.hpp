// SPDX-License-Identifier: Apache-2.0
// Per-vertex normals from the triangles, for extractions that do not give their own.
#pragma once

#include "lasmesh/mesh.hpp"

namespace lasmesh {

// Sets mesh.normals to one unit normal per vertex: the sum of the faces' normals around it, each
// weighted by the face's area (the cross product's length), so tiny slivers barely count. They
// point to the side the triangles face (counter-clockwise winding). A vertex without any area
// around it (unreferenced, or only degenerate faces) gets (0, 0, 1): viewers need unit length.
void compute_vertex_normals(Mesh& mesh);

// Keeps the mesh's own normals (from the surface it was extracted from: smoother than the
// faces') except where one points away from the faces around its vertex, which a viewer would
// shade inside out: there, the faces' area-weighted normal replaces it.
void agree_normals_with_faces(Mesh& mesh);

} // namespace lasmesh
