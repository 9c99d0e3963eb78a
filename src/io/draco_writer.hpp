// SPDX-License-Identifier: Apache-2.0
// Draco output (.drc): the mesh compressed by Google's Draco library, positions quantized, colours
// exact, the local frame kept as geometry metadata so the file reads back in its own coordinates.
#pragma once

#include "lasmesh/mesh.hpp"
#include "lasmesh/mesh_files.hpp"

#include <string>

namespace lasmesh {

// Draco geometry metadata entries: "origin", 3 doubles, the world coordinates of the local frame
// (add them to the positions); the same as three scalar doubles "origin_x", "origin_y",
// "origin_z", which Draco's JavaScript decoder can read (it has no getter for double arrays);
// "cell_size", a double, the grid cell edge (absent when unknown).
inline constexpr const char* draco_origin_entry = "origin";
inline constexpr const char* draco_origin_axis_entries[3] = {"origin_x", "origin_y", "origin_z"};
inline constexpr const char* draco_cell_size_entry = "cell_size";
inline constexpr const char* draco_crs_entry = "crs"; // Mesh::crs, when known

// Unique ids of the attributes in every stream lasmesh writes (the .glb's extension names them).
inline constexpr int draco_position_id = 0;
inline constexpr int draco_color_id = 1;
inline constexpr int draco_normal_id = 2;

// The largest extent of the positions' bounding box: the range Draco quantizes over (0: none).
double position_range(const Mesh& mesh);

// The quantization step of `bits` over the mesh: position_range / (2^bits - 1). Decoded positions
// are within half a step of the originals.
double quantization_step(const Mesh& mesh, int bits);

// The fewest bits, from 8 to 16, whose step is at most a tenth of a grid cell; 14 when the cell
// size is unknown. Never more than 16 by default: some decoders lose precision above that.
int automatic_position_bits(const Mesh& mesh);

// The bits `options` asks for (automatic for 0); throws Error (usage) for bits outside 0-30 or a
// level outside 0-10.
int position_bits(const Mesh& mesh, const DracoOptions& options);

// How the COLOR attribute holds the mesh's 8-bit sRGB colours: as they are (.drc), or converted to
// 16-bit linear values, which glTF's COLOR_0 requires (.glb). Both are normalized and exact.
enum class DracoColor { srgb8, linear16 };

// The mesh as a Draco bitstream (edgebreaker; sequential at level 0): POSITION (float xyz,
// quantized), NORMAL (float xyz, quantized) when the mesh has normals, COLOR (3 components) when
// it has colour, triangles, and the metadata above.
// Throws Error (output) when Draco refuses the mesh, e.g. one without triangles.
std::string encode_draco(const Mesh& mesh, const DracoOptions& options, DracoColor color = DracoColor::srgb8);

// Writes encode_draco(mesh, options) through a temporary file; throws Error (output).
void write_draco(const Mesh& mesh, const std::string& path, const DracoOptions& options);

} // namespace lasmesh
