// SPDX-License-Identifier: Apache-2.0
#include "command_line.hpp"

#include "io/json.hpp"

#include <cctype>

namespace lasmesh::cli {

std::string shell_word(const std::string& text) {
    bool safe = !text.empty();
    for (const char c : text)
        safe = safe && (std::isalnum(static_cast<unsigned char>(c)) ||
                        std::string_view("%+,-./:=@_").find(c) != std::string_view::npos);
    if (safe) return text;
    std::string quoted = "'";
    for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

std::string command_line(const MeshOptions& o) {
    const MeshOptions d; // the defaults
    std::string line = "lasmesh";
    const auto word = [&](const std::string& text) { line += " " + shell_word(text); };
    const auto option = [&](const char* flag, const std::string& value, const std::string& default_value) {
        if (value != default_value) word(flag), word(value);
    };
    const auto flag = [&](const char* name, bool on) {
        if (on) word(name);
    };
    for (const std::string& input : o.inputs) word(input);
    option("--inputs", o.inputs_list, d.inputs_list);
    for (const std::string& output : o.outputs) word("-o"), word(output);
    option("--crs", o.crs, d.crs);
    flag("--skip-bad-inputs", o.skip_bad_inputs);
    if (o.tile != d.tile) word("--tile"), word(format_double(o.tile));
    flag("--refine-thin", o.refine_thin);
    flag("--no-refine-thin", o.no_refine_thin);
    option("--grid", o.grid.grid, d.grid.grid);
    if (o.grid.voxel) word("--voxel"), word(format_double(*o.grid.voxel));
    option("--bounds", o.grid.bounds, d.grid.bounds);
    flag("--scan-bounds", o.grid.scan_bounds);
    option("--device", o.grid.device, d.grid.device);
    if (o.grid.chunk_mb != d.grid.chunk_mb) word("--chunk-mb"), word(format_double(o.grid.chunk_mb));
    if (o.grid.max_memory_mb != d.grid.max_memory_mb) word("--max-memory"), word(format_double(o.grid.max_memory_mb));
    option("--iso", o.iso, d.iso);
    option("--surface", o.surface, d.surface);
    option("--placement", o.placement, d.placement);
    option("--min-piece", o.min_piece, d.min_piece);
    option("--simplify", o.simplify, d.simplify);
    flag("--no-normals", o.no_normals);
    option("--glb-compression", o.glb_compression, d.glb_compression);
    option("--glb-origin", o.glb_origin, d.glb_origin);
    flag("--ascii", o.ascii);
    if (o.draco.position_bits != d.draco.position_bits)
        word("--draco-bits"), word(std::to_string(o.draco.position_bits));
    if (o.draco.level != d.draco.level) word("--draco-level"), word(std::to_string(o.draco.level));
    if (o.threads != d.threads) word("--threads"), word(std::to_string(o.threads));
    option("--report", o.report, d.report);
    option("--preview", o.preview, d.preview);
    return line;
}

} // namespace lasmesh::cli
