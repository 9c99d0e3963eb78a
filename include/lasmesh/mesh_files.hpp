// SPDX-License-Identifier: Apache-2.0
// Mesh files: PLY, Draco (.drc) and glTF binary (.glb), written and read back in the mesh's own
// local frame (its origin and cell size travel with it).
//
//     lasmesh::Mesh mesh = lasmesh::read_mesh("deck.ply");     // .ply (any writer's), .drc, .glb
//     lasmesh::write_mesh(mesh, {"deck.glb"});                  // the format from the extension
//     lasmesh::OutputRequest small{"deck.drc"};
//     small.draco.position_bits = 12;                          // coarser, smaller
//     lasmesh::write_mesh(mesh, small);                         // both throw lasmesh::Error
//
// Files appear complete or not at all: each is written under a temporary name beside its path
// and renamed into place at the end.
//   PLY   binary little-endian (or ASCII): float x, y, z relative to the origin, float nx, ny, nz
//         with normals, uchar red, green, blue with colour; `comment origin X Y Z`.
//   .drc  Draco edgebreaker, positions quantized (default: a tenth of a cell), colours exact,
//         normals to about 0.2 degrees; the origin and cell size as metadata.
//   .glb  glTF 2.0, Y-up (LAS's z is glTF's y), plain (every reader) or Draco-compressed; colour
//         as linear 16-bit COLOR_0; the origin in the scene's and node's extras ("origin", LAS
//         axes), and as the node's translation with GltfOrigin::node.
//   .png  a picture, not the mesh: four views (top, front, side, oblique) rendered on the CPU,
//         1600 x 1200, for reports and for people without a 3D viewer (written only).
//   .html a page that shows the mesh in any web browser, offline: orbit, measure, section, the
//         run's facts; the mesh inside compressed (meshoptimizer, zlib) (written only).
#pragma once

#include "lasmesh/mesh.hpp"

#include <optional>
#include <string>

namespace lasmesh {

enum class MeshFormat {
    ply,   // PLY, binary little-endian unless `ascii`
    draco, // .drc: Draco-compressed mesh
    glb,   // glTF 2.0 binary, plain or Draco-compressed
    png,   // a preview picture of the mesh (written only)
    html,  // a self-contained page showing the mesh in a web browser (written only)
    // An OGC 3D Tiles 1.1 tileset (.json): levels of detail cut into .glb tiles, placed on the
    // globe when the data has a coordinate system. Written by build_mesh only (it needs the grid).
    tileset,
};

struct DracoOptions {
    int position_bits = 0; // position quantization, 1-30; 0: the fewest bits whose step is a tenth of a cell (8-16)
    int level = 7;         // 0 (fastest) to 10 (smallest); Draco's encoding speed is 10 - level
    // Normal quantization in bits (Draco's octahedral coding): 10 keeps them within ~0.2 degrees.
    int normal_bits = 10;
};

// A .glb's geometry: plain (every glTF reader opens it) or Draco-compressed (KHR_draco_mesh_compression).
enum class GltfCompression { none, draco };
// Where a .glb keeps the origin: in extras only (positions stay local), or also as the node's
// translation, so geo viewers place the mesh at its world coordinates (at float32 precision).
enum class GltfOrigin { extras, node };

// One file to write. Its folder is checked before anything is read, so nobody waits to learn
// that it cannot be written; the file appears complete or not at all.
struct OutputRequest {
    std::string path;
    std::optional<MeshFormat> format;                        // default: from the extension (.ply, .drc, .glb)
    bool ascii = false;                                      // ply only
    DracoOptions draco;                                      // draco, and glb with GltfCompression::draco
    GltfCompression glb_compression = GltfCompression::none; // glb only: plain opens everywhere
    GltfOrigin glb_origin = GltfOrigin::extras;              // glb only: translation node or not
};

// The format an output path's extension names (.ply, .drc, .glb, .png, .html, .json: a tileset; any
// case), or nullopt.
std::optional<MeshFormat> format_from_extension(const std::string& path);

// Writes `mesh` as `output` asks; `name` names the .glb's scene, node, mesh and material.
// Throws Error: usage for an unknown extension, output when the file cannot be written or the
// mesh has no triangles (Draco and glTF need some).
void write_mesh(const Mesh& mesh, const OutputRequest& output, const std::string& name = "mesh");

// Reads a .ply (lasmesh's or any triangle PLY), .drc or .glb (not .png or .html) by its extension, into a Mesh in the
// file's local frame. Throws Error: usage for another extension, input naming the file, the byte
// offset and what was expected.
Mesh read_mesh(const std::string& path);

} // namespace lasmesh
