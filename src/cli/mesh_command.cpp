// SPDX-License-Identifier: Apache-2.0
// `lasmesh INPUT -o OUT.ply ...`: the option text turned into BuildOptions, one call to the
// library, and the summary or the report printed. The pipeline itself is build_mesh.
#include "mesh_command.hpp"

#include "io/write_into.hpp"
#include "lasmesh/error.hpp"
#include "mesh_observer.hpp"
#include "mesh_report.hpp"
#include "option_parsing.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

namespace lasmesh::cli {

namespace {

// Draco's encoder needs about 4 * 2^bits bytes whatever the mesh (measured with libdraco 1.5.5:
// 1.1 GB at 28 bits, 4.1 GB and 35 s at 30, 170 MB at 24). 24 bits already put every vertex within
// 1/16,000,000 of the mesh's extent, far below any grid cell, so more is refused, not attempted.
CLI::Validator draco_bits_check() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            int bits = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), bits);
            if (ec != std::errc() || end != text.data() + text.size() || bits < 1 || bits > 24)
                return "expected 1 to 24 bits, got \"" + text +
                       "\" (Draco needs about 4 * 2^bits bytes: 1 GB at 28 "
                       "bits; 24 already resolve 1/16,000,000 of the mesh's extent)";
            return "";
        },
        "1-24");
}

} // namespace

void add_meshing_options(CLI::App& app, MeshOptions& o, bool with_grid) {
    app.add_option("-o,--output", o.outputs,
                   "Output mesh, repeatable; the extension sets the format: .ply (binary; --ascii for text), "
                   ".drc (Draco), .glb (glTF 2.0 binary; see --glb-compression), .png (a picture: see --preview), "
                   ".html (a page showing the mesh in a web browser, offline, with measuring), "
                   ".json (a 3D Tiles tileset of .glb tiles, levels of detail)")
        ->type_name("FILE");
    if (with_grid) add_grid_options(app, o.grid);
    app.add_option("--iso", o.iso, "Points per cell at the surface (cells with more are inside), or auto")
        ->type_name("N|auto")
        ->capture_default_str();
    app.add_option("--surface", o.surface,
                   "sheet: one open sheet through the points of each surface (accurate below the cell); "
                   "closed: a watertight surface around the occupied cells (solids, 3D printing)")
        ->type_name("sheet|closed")
        ->capture_default_str()
        ->check(one_of({"sheet", "closed"}));
    app.add_option("--placement", o.placement,
                   "With --surface closed: vertices on the scanned surface (surface) or on the iso level set "
                   "as in classic marching cubes (iso)")
        ->type_name("surface|iso")
        ->capture_default_str();
    app.add_option("--min-piece", o.min_piece,
                   "Remove isolated pieces smaller than this bounding-box diagonal: a percentage of the "
                   "whole mesh's diagonal (5%), a length (in the unit of --voxel), or 0 to keep all")
        ->type_name("P%|LENGTH")
        ->capture_default_str();
    app.add_option("--simplify", o.simplify,
                   "Simplify until the surface would move more than this: a length (in the unit of --voxel), a "
                   "fraction of a cell (0.5cell), or 0 for none")
        ->type_name("LENGTH|Fcell")
        ->capture_default_str();
    app.add_flag("--no-normals", o.no_normals, "No per-vertex normals in the outputs (they are on by default)");
    app.add_option("--glb-compression", o.glb_compression,
                   "none: a plain .glb every viewer opens; draco: smaller, for three.js and the web")
        ->type_name("none|draco")
        ->capture_default_str();
    app.add_option("--glb-origin", o.glb_origin,
                   "Where the .glb keeps the world origin: extras (data only, the mesh stays local) or node "
                   "(also a node translation, for geo viewers; float32 in most)")
        ->type_name("extras|node")
        ->capture_default_str();
    app.add_flag("--ascii", o.ascii, "Write ASCII PLY instead of binary");
    app.add_option("--draco-bits", o.draco.position_bits,
                   "Position quantization of .drc and .glb, in bits (default: the fewest whose step is at most a "
                   "tenth of a cell, 8 to 16); at most 24")
        ->type_name("BITS")
        ->check(draco_bits_check());
    app.add_option("--draco-level", o.draco.level, "Draco compression level, 0 (fastest) to 10 (smallest)")
        ->type_name("0-10")
        ->capture_default_str()
        ->check(whole_number(0, 10));
    app.add_option("--threads", o.threads, "Threads for extraction and LAZ decoding, 1 to 1024 (default: all cores)")
        ->type_name("N")
        ->check(whole_number(1, 1024));
    app.add_option("--report", o.report, "Also write the summary as JSON to this file (for pipelines)")
        ->type_name("FILE.json");
    app.add_option("--preview", o.preview,
                   "Also write a picture of the mesh: four views (top, front, side, oblique) as PNG, for reports "
                   "and people without a 3D viewer (as -o FILE.png)")
        ->type_name("FILE.png");
    app.add_flag("-q,--quiet", o.quiet, "No progress line and no summary; errors only");
    app.add_flag("-v,--verbose", o.verbose, "Details of each stage as it ends");
}

void add_mesh_options(CLI::App& app, MeshOptions& o) {
    app.add_option("INPUT", o.inputs,
                   "LAS or LAZ files (gzip, bzip2, xz, zstd recognised), meshed as one survey; or - for standard "
                   "input, alone")
        ->type_name("FILE...");
    app.add_option("--inputs", o.inputs_list,
                   "Also read the inputs listed in this file, one path a line (relative to the list's folder; "
                   "blank lines and lines starting with # skipped); - reads the list from standard input")
        ->type_name("LIST");
    app.add_option("--crs", o.crs,
                   "Mesh in this coordinate system (EPSG:CODE or a WKT); inputs in others are transformed with "
                   "PROJ (default: the CRS most inputs declare, longitude/latitude projected to the UTM zone of "
                   "the data's centre)")
        ->type_name("CRS");
    app.add_flag("--skip-bad-inputs", o.skip_bad_inputs,
                 "With several inputs: leave out, and name, an input that cannot be read, instead of stopping");
    add_meshing_options(app, o, true);
    app.add_option("--tile", o.tile,
                   "A tileset's finest tiles: their edge in x and y, in the CRS's unit (rounded up to 4 cells); "
                   "the tileset `lasmesh plan --tile SIZE` and its merge write (default: 64 cells)")
        ->type_name("SIZE");
    add_thin_parts_options(app, o, "from a second read of the input files");
}

void add_thin_parts_options(CLI::App& app, MeshOptions& o, const std::string& reading) {
    CLI::Option* refine =
        app.add_flag("--refine-thin", o.refine_thin,
                     "Mesh thin parts (rails, posts, cables: thinner than about a cell in two directions) at half "
                     "the cell, " +
                         reading +
                         ", whatever the grid and however sparse the points (by default: with the automatic grid, "
                         "when its occupied cells hold a median of 12 points or more, from files); the sheet only");
    app.add_flag("--no-refine-thin", o.no_refine_thin, "One cell size everywhere, however dense the points")
        ->excludes(refine);
}

void check_tile_option(const BuildOptions& b) {
    if (b.tile_size != 0 && std::none_of(b.outputs.begin(), b.outputs.end(), [](const OutputRequest& output) {
            return output_format(output) == MeshFormat::tileset;
        }))
        throw Error(ErrorKind::usage, "--tile sets a 3D Tiles tileset's tiles: give an output ending in .json", "tile");
}

BuildOptions build_options(const MeshOptions& o, bool need_output) {
    if (need_output && o.outputs.empty() && o.preview.empty())
        throw Error(ErrorKind::usage, "no output: give -o OUT.ply, OUT.drc or OUT.glb");
    BuildOptions b;
    const GltfCompression glb_compression = parse_glb_compression(o.glb_compression);
    const GltfOrigin glb_origin = parse_glb_origin(o.glb_origin);
    for (const std::string& path : o.outputs)
        b.outputs.push_back({path, std::nullopt, o.ascii, o.draco, glb_compression, glb_origin});
    if (!o.preview.empty()) {
        OutputRequest preview;
        preview.path = o.preview;
        preview.format = MeshFormat::png;
        b.outputs.push_back(preview);
    }
    b.report = o.report;
    b.refine_thin = o.refine_thin      ? ThinRefinement::always
                    : o.no_refine_thin ? ThinRefinement::never
                                       : ThinRefinement::automatic;
    const AccumulateOptions accumulate = accumulate_options(o.grid);
    b.grid = accumulate.grid;
    b.bounds = accumulate.bounds;
    b.slice_bytes = accumulate.slice_bytes;
    b.max_memory = accumulate.max_memory;
    const double iso = parse_iso(o.iso);
    if (iso >= 0) b.iso = iso;
    b.min_piece = parse_min_piece(o.min_piece);
    b.simplify = parse_simplify(o.simplify);
    b.normals = !o.no_normals;
    b.placement = parse_placement(o.placement);
    b.surface = parse_surface(o.surface);
    b.device = o.grid.device;
    b.threads = o.threads;
    b.scan_bounds = o.grid.scan_bounds;
    b.skip_bad_inputs = o.skip_bad_inputs;
    b.crs = o.crs;
    b.tile_size = o.tile;
    return b;
}

std::vector<std::string> all_inputs(const MeshOptions& o) {
    std::vector<std::string> inputs = o.inputs;
    if (o.inputs_list.empty()) return inputs;
    std::ifstream file;
    if (o.inputs_list != "-") {
        file.open(o.inputs_list);
        if (!file) throw Error(ErrorKind::input, o.inputs_list + ": cannot open the list of inputs");
    }
    std::istream& list = o.inputs_list == "-" ? std::cin : file;
    const std::string name = o.inputs_list == "-" ? "the list on standard input" : o.inputs_list;
    const std::filesystem::path folder =
        o.inputs_list == "-" ? std::filesystem::path() : std::filesystem::path(o.inputs_list).parent_path();
    std::size_t listed = 0;
    for (std::string line; std::getline(list, line);) {
        while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back(); // \r too
        if (line.empty() || line.front() == '#') continue;
        const std::filesystem::path path(line);
        inputs.push_back(path.is_absolute() ? line : (folder / path).string());
        ++listed;
    }
    if (list.bad()) throw Error(ErrorKind::input, name + ": reading the list of inputs failed");
    if (listed == 0) throw Error(ErrorKind::usage, name + " lists no input (one path a line)", "inputs");
    return inputs;
}

void run_with_summary(const MeshOptions& o, BuildOptions options,
                      const std::function<BuildResult(const BuildOptions&, BuildObserver&)>& run,
                      std::ostream& summary) {
    SummaryContext context;
    context.min_piece_text = o.min_piece;
    context.relative_min_piece = options.min_piece.relative;
    context.draco = o.draco;
    context.simplify_text = o.simplify;
    context.any_draco = std::any_of(options.outputs.begin(), options.outputs.end(), [](const OutputRequest& out) {
        const std::optional<MeshFormat> format = format_from_extension(out.path);
        return format == MeshFormat::draco ||
               (format == MeshFormat::glb && out.glb_compression == GltfCompression::draco);
    });
    options.keep_mesh = context.any_draco && !o.quiet; // the Draco line reports bits and step of the mesh
    MeshObserver observer(summary, o.progress, o.verbose, o.quiet);
    const BuildResult result = run(options, observer);
    observer.clear();
    context.mesh = result.mesh ? &*result.mesh : nullptr;
    if (!o.quiet) print_summary(result.report, context, summary);
}

void run_mesh(const MeshOptions& o, std::ostream& summary) {
    const std::vector<std::string> inputs = all_inputs(o);
    const BuildOptions options = build_options(o);
    check_tile_option(options);
    run_with_summary(
        o, options,
        [&](const BuildOptions& options, BuildObserver& observer) { return build_mesh(inputs, options, &observer); },
        summary);
}

} // namespace lasmesh::cli
