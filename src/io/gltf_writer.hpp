// SPDX-License-Identifier: Apache-2.0
// glTF 2.0 binary output (.glb): one scene, one node, one mesh with one primitive, one material,
// all named after the input. Plain by default (every glTF reader opens it: Blender without a
// Draco library, assimp and so Open3D, gltfpack); Draco-compressed on request, for three.js and
// the web, through the KHR_draco_mesh_compression extension.
//
// - Axes: glTF is Y-up, LAS is Z-up. The node's rotation (-90 degrees about x, the quaternion
//   [-sqrt(1/2), 0, 0, sqrt(1/2)]) turns the mesh so LAS's up is glTF's up: glTF x, y, z are LAS
//   x, z, -y.
// - Georeference: positions stay in the mesh's local frame (float32 cannot hold centimetres at
//   UTM coordinates, and viewers store node transforms as float32 too). The origin is kept as
//   data: the scene's and the node's `extras` hold "origin" (LAS X, Y, Z, doubles: add them to
//   local LAS coordinates), "origin_gltf" (the same in glTF axes: X, Z, -Y) and "cell_size".
//   GltfOrigin::node also sets the node's translation to origin_gltf, so geo viewers place the
//   mesh at its world coordinates (at float32 precision in most of them). read_glb undoes both.
// - Normals: NORMAL (float, unit length) when the mesh has normals.
// - Colour: COLOR_0 holds linear values (glTF's convention), converted from LAS's sRGB, as
//   normalized 16-bit words (8 bits would lose the dark tones); plain files pad each to 8 bytes,
//   as glTF wants vertex attributes 4-byte aligned.
// - Indices: 16-bit when the mesh has at most 65,535 vertices (assimp reads only those from a
//   Draco primitive), 32-bit otherwise.
// - Material: pbrMetallicRoughness with metallicFactor 0 and roughnessFactor 1 (a matte surface
//   showing the vertex colours), double-sided: meshes may be open sheets, seen from both sides.
#pragma once

#include "io/draco_writer.hpp"
#include "lasmesh/mesh.hpp"
#include "lasmesh/mesh_files.hpp"

#include <string>

namespace lasmesh {

struct GltfOptions {
    GltfCompression compression = GltfCompression::none;
    GltfOrigin origin = GltfOrigin::extras;
    std::string name = "mesh"; // of the scene, node, mesh and material: build_mesh uses the input's stem
    DracoOptions draco;        // with GltfCompression::draco
};

// The GLB bytes; throws Error (output) when the mesh has no triangles or Draco refuses it.
std::string encode_glb(const Mesh& mesh, const GltfOptions& options);

// Writes encode_glb(mesh, options) through a temporary file; throws Error (output).
void write_glb(const Mesh& mesh, const std::string& path, const GltfOptions& options);

} // namespace lasmesh
