// glTF 2.0 binary output (.glb): one node, one mesh, one primitive compressed with Draco through
// the KHR_draco_mesh_compression extension, for three.js, Blender and other viewers.
//
// - Axes: glTF is Y-up, LAS is Z-up. The node's rotation (-90 degrees about x, the quaternion
//   [-sqrt(1/2), 0, 0, sqrt(1/2)]) turns the mesh so LAS's up is glTF's up: glTF x, y, z are LAS
//   x, z, -y. The node's translation is the mesh origin in those axes, (X, Z, -Y), so the node
//   places the mesh at its world coordinates, rotated. read_glb undoes both.
// - Colour: COLOR_0 holds linear values (glTF's convention), converted from LAS's sRGB, as
//   normalized 16-bit words: 8 bits would lose the dark tones.
// - Material: one, pbrMetallicRoughness with metallicFactor 0 and roughnessFactor 1 (a matte
//   surface showing the vertex colours), single-sided: the mesh is closed and faces outward.
#pragma once

#include "lasmesh/io/draco_writer.hpp"
#include "lasmesh/mesh.hpp"

#include <string>

namespace lasmesh {

// The GLB bytes; throws Error (output) when Draco refuses the mesh, e.g. one without triangles.
std::string encode_glb(const Mesh& mesh, const DracoOptions& options);

// Writes encode_glb(mesh, options) through a temporary file; throws Error (output).
void write_glb(const Mesh& mesh, const std::string& path, const DracoOptions& options);

} // namespace lasmesh
