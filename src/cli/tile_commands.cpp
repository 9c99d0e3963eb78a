// SPDX-License-Identifier: Apache-2.0
#include "tile_commands.hpp"

#include "io/json.hpp"
#include "lasmesh/build_mesh.hpp"
#include "lasmesh/error.hpp"
#include "mesh_observer.hpp"
#include "number_text.hpp"
#include "option_parsing.hpp"

#include <charconv>
#include <cstdlib>
#include <set>

namespace lasmesh::cli {

CLI::App* add_plan_command(CLI::App& app, PlanOptions& o) {
    CLI::App* plan = app.add_subcommand(
        "plan", "Plan a survey's meshing over many machines: read the inputs' headers (and COPC files' "
                "hierarchies), fix the grid, cut it into "
                "tiles, and say how to run them (lasmesh tile) and join them (lasmesh merge)");
    plan->footer("Examples:\n"
                 "  lasmesh plan scans/*.laz --tile 250 -o site.plan.json\n"
                 "  sbatch --array=0-15 lasmesh-tile.sbatch site.plan.json   (deploy/slurm/ in the sources)\n"
                 "  seq 0 15 | xargs -P 4 -I K lasmesh tile site.plan.json --index K\n"
                 "  lasmesh merge site.plan.json -o site/tileset.json");
    plan->add_option("INPUT", o.survey.inputs, "LAS or LAZ files (gzip, bzip2, xz, zstd recognised), one survey")
        ->type_name("FILE...");
    plan->add_option("--inputs", o.survey.inputs_list,
                     "Also the inputs listed in this file, one path a line (relative to the list's folder)")
        ->type_name("LIST");
    plan->add_option("--crs", o.survey.crs, "Mesh in this coordinate system (EPSG:CODE or a WKT); as for meshing")
        ->type_name("CRS");
    plan->add_option("--tile", o.tile,
                     "A tile's edge in x and y, in the CRS's unit (rounded up to 4 cells); default: about 20 "
                     "million points a tile")
        ->type_name("SIZE");
    plan->add_option("-o,--output", o.output, "The plan (JSON); its tiles' cells go to a folder beside it")
        ->type_name("PLAN.json")
        ->required();
    add_cell_options(*plan, o.survey.grid, false); // a plan reads headers only: no scan, no device
    return plan;
}

CLI::App* add_tile_command(CLI::App& app, TileOptions& o) {
    CLI::App* tile = app.add_subcommand(
        "tile", "Read the inputs of one tile of a plan (of a COPC file, only the octree nodes that touch it) and "
                "write its cells' sums (a task of an array job)");
    tile->footer("Examples:\n"
                 "  lasmesh tile site.plan.json --index 3\n"
                 "  lasmesh tile site.plan.json        in a Slurm array task or a Kubernetes Indexed Job");
    tile->add_option("PLAN", o.plan, "The plan (lasmesh plan wrote it)")->type_name("PLAN.json")->required();
    tile->add_option("--index", o.index,
                     "The tile, from 0; default: SLURM_ARRAY_TASK_ID, else JOB_COMPLETION_INDEX (Kubernetes)")
        ->type_name("K");
    add_device_options(*tile, o.device);
    tile->get_option("--chunk-mb")
        ->description("Largest slice of records uploaded at once, MiB (default 2 for a tile job: its share of "
                      "the grid is small, so the slices are most of its memory)");
    tile->add_option("--threads", o.threads, "Threads for LAZ decoding, 1 to 1024 (default: all cores)")
        ->type_name("N")
        ->check(whole_number(1, 1024));
    tile->add_flag("-q,--quiet", o.quiet, "Errors only");
    return tile;
}

CLI::App* add_merge_command(CLI::App& app, MergeOptions& o) {
    CLI::App* merge = app.add_subcommand(
        "merge", "Join the tiles of a plan into the grid one machine would have read, and mesh it: the same "
                 "outputs as meshing the inputs here, byte for byte");
    merge->footer("Examples:\n"
                  "  lasmesh merge site.plan.json -o site/tileset.json\n"
                  "  lasmesh merge site.plan.json -o site.glb --simplify 0.25cell");
    merge->add_option("PLAN", o.plan, "The plan whose tiles have all run")->type_name("PLAN.json")->required();
    add_meshing_options(*merge, o.mesh, false);
    add_thin_parts_options(*merge, o.mesh,
                           "as the main job does: the merge reads every input again for the points near them (the "
                           "tiles hold the grid's cells only)");
    merge->add_flag("--in-tiles", o.in_tiles,
                    "Mesh a tileset's sheet tile by tile from the tiles' files, never holding the plan's grid "
                    "whole: the same outputs, slower on one machine");
    return merge;
}

namespace {

// "2 COPC inputs: the tiles read only the octree nodes that touch them, 1.31x their points in all\n",
// or "" when no input is read by its nodes.
std::string copc_line(const TilePlan& plan) {
    std::set<std::size_t> inputs;
    std::uint64_t planned = 0, points = 0;
    for (const PlannedTile& tile : plan.tiles)
        for (const PlannedChunks& c : tile.chunks) {
            inputs.insert(c.input);
            for (const std::uint64_t n : c.points) planned += n;
        }
    if (inputs.empty()) return "";
    for (const std::size_t i : inputs) points += plan.inputs[i].points;
    return std::to_string(inputs.size()) + (inputs.size() == 1 ? " COPC input" : " COPC inputs") +
           ": the tiles read only the octree nodes that touch them, " +
           two_digits(points ? double(planned) / double(points) : 0.0) + "x " + (inputs.size() == 1 ? "its" : "their") +
           " points in all\n";
}

// "the tile jobs read the inputs' points 3.2 times in all: ...\n": each tile reads every input
// its bounds touch whole (LAS and LAZ have no spatial index; a COPC input, its nodes), so an input
// larger than a tile is read once by each tile it touches, and that reading is what tile jobs add
// to one machine's CPU (docs/benchmarks.md, "A survey over many machines").
std::string reading_line(const TilePlan& plan) {
    std::uint64_t read = 0, points = 0;
    for (const PlannedInput& input : plan.inputs) points += input.points;
    for (const PlannedTile& tile : plan.tiles) read += tile.points; // its inputs' (or nodes') points
    const double times = points ? double(read) / double(points) : 0.0;
    return "the tile jobs read the inputs' points " + two_digits(times) + " times in all" +
           (times >= 2 ? ": a tile reads whole each input (of COPC, each node) it touches; larger tiles read less\n"
                       : "\n");
}

} // namespace

void run_plan(const PlanOptions& o, std::ostream& out) {
    BuildOptions options;
    const AccumulateOptions accumulate = accumulate_options(o.survey.grid);
    options.grid = accumulate.grid;
    options.bounds = accumulate.bounds;
    options.crs = o.survey.crs;
    TilePlan plan = plan_tiles(all_inputs(o.survey), options, o.tile);
    write_plan(plan, o.output);
    std::uint64_t points = 0;
    for (const PlannedInput& input : plan.inputs) points += input.points;
    const std::string unit = plan.unit.empty() ? "" : " " + plan.unit;
    const std::string last = std::to_string(plan.tiles.size() - 1);
    const std::string& name = o.output;
    out << name << ": " << plan.tiles.size() << " tiles of " << four_digits(plan.tile_size) << " x "
        << four_digits(plan.tile_size) << unit << " (" << plan.tile_cells << " x " << plan.tile_cells << " cells of "
        << four_digits(plan.grid.cell_size) << "), " << points << " points in " << plan.inputs.size() << " inputs\n"
        << copc_line(plan) << reading_line(plan) << "run every tile, K from 0 to " << last
        << ", on a cluster or here:\n"
        << "  sbatch --array=0-" << last << " lasmesh-tile.sbatch " << name << "\n"
        << "  seq 0 " << last << " | xargs -P 4 -I K lasmesh tile " << name << " --index K\n"
        << "then join them:\n"
        << "  lasmesh merge " << name << " -o tileset.json\n"
        << "(the tileset one machine writes with lasmesh INPUTS... --tile " << format_double(plan.tile_size)
        << " -o tileset.json)\n";
}

std::size_t tile_index(const std::optional<std::size_t>& given, const char* slurm, const char* kubernetes) {
    if (given) return *given;
    for (const auto& [name, value] : {std::pair{"SLURM_ARRAY_TASK_ID", slurm}, {"JOB_COMPLETION_INDEX", kubernetes}}) {
        if (!value) continue;
        const std::string text = value;
        std::size_t index = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), index);
        if (ec != std::errc() || end != text.data() + text.size() || text.empty())
            throw Error(ErrorKind::usage, std::string(name) + " is \"" + text + "\", not a tile number: give --index K",
                        "index");
        return index;
    }
    throw Error(ErrorKind::usage,
                "which tile? give --index K (or run it as a Slurm array task or a Kubernetes "
                "Indexed Job, which say it)",
                "index");
}

void run_tile(const TileOptions& o, std::ostream& log) {
    const TilePlan plan = read_plan(o.plan);
    BuildOptions options;
    const AccumulateOptions device = accumulate_options(o.device);
    options.device = o.device.device;
    options.slice_bytes = device.slice_bytes;
    options.max_memory = device.max_memory;
    options.threads = o.threads;
    const std::size_t index =
        tile_index(o.index, std::getenv("SLURM_ARRAY_TASK_ID"), std::getenv("JOB_COMPLETION_INDEX"));
    const TileReport report = lasmesh::run_tile(plan, index, options);
    if (!o.quiet)
        log << "tile " << report.index << " of " << plan.tiles.size() << ": " << report.points_read
            << " points read from " << report.inputs_read << " inputs, " << report.points_in_tile << " in its "
            << report.occupied_cells << " cells; wrote " << report.path << " (" << megabytes(report.bytes) << ") in "
            << two_digits(report.seconds) << " s, peak memory " << megabytes(report.peak_rss_bytes) << "\n";
}

void run_merge(const MergeOptions& o, std::ostream& summary) {
    const TilePlan plan = read_plan(o.plan);
    BuildOptions options = build_options(o.mesh);
    options.mesh_in_tiles = o.in_tiles;
    try {
        run_with_summary(
            o.mesh, options,
            [&](const BuildOptions& options, BuildObserver& observer) { return merge_tiles(plan, options, &observer); },
            summary);
    } catch (const Error& e) {
        if (e.option() != "tiles") throw;
        throw Error(e.kind(), std::string(e.what()) + ": lasmesh tile " + o.plan +
                                  " --index K for each, or sbatch --array=" + e.suggestion() + " lasmesh-tile.sbatch " +
                                  o.plan);
    }
}

} // namespace lasmesh::cli
