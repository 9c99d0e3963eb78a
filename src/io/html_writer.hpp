// SPDX-License-Identifier: Apache-2.0
// A self-contained HTML page that shows the mesh (.html): it opens offline, by double-click,
// with no server and nothing fetched. The page holds three things, each base64 text inside a
// <script> element the browser does not run:
// - the viewer: three.js and the page's own code (src/io/html/viewer.js), bundled and
//   gzip-compressed when lasmesh is built (tools/bundle_viewer.sh), unpacked by the browser's
//   DecompressionStream;
// - the mesh, compressed by meshoptimizer's vertex and index codecs (Kapoulkine's, as glTF's
//   EXT_meshopt_compression uses them), then zlib: positions as 32-bit integers in steps of at most
//   a thousandth of a cell and 0.0001 units (a power of two, so that step times integer is exact;
//   three.js's Draco decoder would add 250 kB to the page, meshoptimizer's 29 kB), sRGB colours as
//   bytes, normals as signed bytes, triangles reordered for the GPU's vertex cache;
// - the run's facts (the RunReport as JSON, when build_mesh writes it), shown in a panel;
// - with a heat map (written by lasmesh compare), a second colour per vertex and its
//   distance to the points, which the page shows on request.
// Layout of the mesh data (before zlib): "LMSH", u32 version (1), u32 length of a JSON header,
// the header (counts, origin, step, buffers' offsets and lengths, facts), then the buffers, each
// starting at a multiple of 4.
#pragma once

#include "lasmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace lasmesh {

struct HtmlOptions {
    std::string name = "mesh"; // the page's title: build_mesh uses the input's stem
    // The run's RunReport as JSON, or empty; what differs from run to run (device, timings,
    // memory, outputs) is left out, so that the same run writes the same bytes.
    std::string facts_json;
    // A heat map the page can show instead of the colours (lasmesh compare): per vertex its
    // colour on the ramp and its distance to the points, and the distance shown red. Empty: none.
    std::vector<std::array<std::uint8_t, 3>> heat_colors;
    std::vector<double> heat_distance;
    double heat_scale = 0;
};

// The page's bytes. Throws Error (output) when the mesh has no triangles, or when this lasmesh
// was built without its viewer (three.js from npm was not there at build time).
std::string encode_html(const Mesh& mesh, const HtmlOptions& options);

// The mesh data alone: what the page decodes (for the tests), and that compressed by zlib
// (what the page holds in base64; what `lasmesh view` sends the page for a new mesh).
std::string encode_html_mesh(const Mesh& mesh, const HtmlOptions& options);
std::string compress_html_mesh(const Mesh& mesh, const HtmlOptions& options);

// The page around mesh data compressed by compress_html_mesh. Throws Error (output) when this
// lasmesh was built without its viewer.
std::string html_page_with(const std::string& compressed_mesh);

// The viewer script, gzip-compressed and base64-encoded, and the page around it (generated at
// build time); empty when lasmesh was built without them.
std::string_view html_viewer_script();
std::string_view html_viewer_page();

} // namespace lasmesh
