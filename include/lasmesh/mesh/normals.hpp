// Per-vertex normals from the triangles, for extractions that do not give their own.
#pragma once

#include "lasmesh/mesh.hpp"

namespace lasmesh {

// Sets mesh.normals to one unit normal per vertex: the sum of the faces' normals around it, each
// weighted by the face's area (the cross product's length), so tiny slivers barely count. They
// point to the side the triangles face (counter-clockwise winding). A vertex without any area
// around it (unreferenced, or only degenerate faces) gets (0, 0, 1): viewers need unit length.
void compute_vertex_normals(Mesh& mesh);

} // namespace lasmesh
