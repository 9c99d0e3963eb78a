// SPDX-License-Identifier: Apache-2.0
// Option text to typed values: the command line's spellings (--grid 256x512x256, --iso auto,
// --min-piece 5%) live here and nowhere in the library, which takes the typed values only.
// Each parser throws Error (usage) quoting the option and the text it could not use.
#pragma once

#include "lasmesh/build_mesh.hpp"
#include "lasmesh/grid.hpp"
#include "lasmesh/mesh_pieces.hpp"
#include "lasmesh/surface.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace lasmesh::cli {

// "--grid": "256" (cells along the longest axis) or "256x512x256".
GridRequest parse_grid_request(const std::string& text);
// "--voxel": a cell edge; refused unless positive and finite.
GridRequest voxel_request(double cell_size);
// "--bounds": "minx,miny,minz,maxx,maxy,maxz".
Bounds parse_bounds(const std::string& text);
// "--iso": a non-negative number or "auto" (returns a negative value for auto).
double parse_iso(const std::string& text);
// "--placement": "surface" or "iso".
VertexPlacement parse_placement(const std::string& text);
// "--min-piece": "5%" (of the mesh diagonal), "2.5" (file units) or "0" (keep all).
MinPiece parse_min_piece(const std::string& text);
// "--simplify": "0.5cell" (of a grid cell), "0.02" (file units) or "0" (off).
SimplifyRequest parse_simplify(const std::string& text);
// "--glb-compression": "none" or "draco".
GltfCompression parse_glb_compression(const std::string& text);
// "--glb-origin": "extras" or "node".
GltfOrigin parse_glb_origin(const std::string& text);

// A check for options that take a positive, finite number. CLI11's PositiveNumber says "not in
// range 2.2250738585072014e-308 to 1.7976931348623157e+308"; this says what is wanted.
CLI::Validator positive_number();

// " (--grid 512)", " (--scan-bounds or --bounds)": the flags that set the library options an
// error names (Error::option, Error::suggestion), to append to its message; empty when it names none.
std::string flag_hint(const Error& error);

// Validators whose messages say what was expected and what was given, in the words of our own
// errors ("expected a whole number from 1 to 1024, got \"abc\"").
CLI::Validator whole_number(std::uint64_t lowest, std::uint64_t highest);
CLI::Validator one_of(const std::vector<std::string>& words);

SurfaceKind parse_surface(const std::string& text);

} // namespace lasmesh::cli
