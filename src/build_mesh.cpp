// SPDX-License-Identifier: Apache-2.0
// The pipeline behind build_mesh: read -> accumulate -> extract -> remove small pieces ->
// simplify -> normals -> write each output, timed per stage and per output.
#include "lasmesh/build_mesh.hpp"
#include "build_steps.hpp"
#include "number_text.hpp"

#include "byte_order.hpp"
#include "grid/auto_grid.hpp"
#include "grid/cell_set.hpp"
#include "grid/cell_sums.hpp"
#include "grid/compute_device.hpp"
#include "grid/records_in_cells.hpp"
#include "grid/thin_parts.hpp"
#include "io/output_file.hpp"
#include "io/ply_writer.hpp"
#include "io/same_file.hpp"
#include "io/tileset_writer.hpp"
#include "io/write_into.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/normals.hpp"
#include "measure/level_error.hpp"
#include "mesh/marching_cubes.hpp"
#include "mesh/mesh_edit.hpp"
#include "mesh/seam.hpp"
#include "mesh/surface_sheet.hpp"
#include "read/crs.hpp"
#include "read/input_stream.hpp"
#include "read/las_scan.hpp"
#include "read/survey.hpp"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <mutex>
#include <stdexcept>

#include <sys/resource.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <unistd.h>

namespace lasmesh {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Resident memory now (Linux: /proc/self/statm, in pages); 0 where unknown.
std::uint64_t resident_bytes() {
    std::ifstream statm("/proc/self/statm");
    std::uint64_t size = 0, resident = 0;
    if (!(statm >> size >> resident)) return 0;
    return resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
}

std::uint64_t peak_rss_bytes() {
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024; // Linux reports kilobytes
}

namespace {

// The name of the .glb's scene, node, mesh and material: the input's file name without extension.
std::string mesh_name(const std::string& input) {
    const std::string stem = std::filesystem::path(input).stem().string();
    return input == "-" || stem.empty() ? "lasmesh" : stem;
}

// The surface cells (count above the iso) of `grid`, and of the grid with cells twice as large
// (2 x 2 x 2 merged): how the surface shrinks with the grid, which at sparse grids (a few points a
// cell) is far slower than the square of the grid a dense surface follows.
std::pair<std::uint64_t, std::uint64_t> surface_cells_and_coarser(const CellGrid& grid, double iso) {
    std::uint64_t fine = 0;
    std::vector<std::pair<std::uint64_t, std::uint64_t>> coarse; // (coarse cell, count)
    coarse.reserve(grid.cells.size());
    const std::uint64_t nx = (grid.spec.dims[0] + 1) / 2, ny = (grid.spec.dims[1] + 1) / 2;
    grid.for_each_cell([&](const std::array<std::int64_t, 3>& at, std::uint64_t r) {
        fine += static_cast<double>(grid.cells[r].count) > iso;
        coarse.emplace_back((std::uint64_t(at[2] / 2) * ny + std::uint64_t(at[1] / 2)) * nx + std::uint64_t(at[0] / 2),
                            grid.cells[r].count);
    });
    std::sort(coarse.begin(), coarse.end());
    std::uint64_t coarser = 0;
    for (std::size_t i = 0; i < coarse.size();) {
        std::uint64_t count = 0;
        const std::uint64_t key = coarse[i].first;
        for (; i < coarse.size() && coarse[i].first == key; ++i) count += coarse[i].second;
        coarser += static_cast<double>(count) > iso;
    }
    return {fine, coarser};
}

// Refuses, before extracting, a surface whose extraction and outputs would take the run past
// max_memory. Per surface cell (count above the iso) and per grid cell, the bytes measured on
// the deck at grids 256-2048, rounded up: the cell's plane, normal and orientation links, the
// mesh around it; the Draco and glTF encoders' copy of the mesh.
void check_extraction_memory(const CellGrid& grid, double iso, const BuildOptions& o,
                             const std::vector<MeshFormat>& formats, const std::string& input,
                             std::uint64_t in_use_before_grid) {
    bool encoded = false;
    for (const MeshFormat format : formats) encoded = encoded || format != MeshFormat::ply;
    // The grid is released before the outputs are written, so the encoders' copy replaces it.
    const std::uint64_t fixed = 64ull << 20;
    const auto need_for = [&](double surface_cells, double bricks) {
        return std::max(surface_cells * 230 + bricks * CellGrid::brick_cells * 10, encoded ? surface_cells * 400 : 0.0);
    };
    std::uint64_t surface_cells = 0;
    for (const CellSums& cell : grid.cells) surface_cells += static_cast<double>(cell.count) > iso;
    const double need = static_cast<double>(fixed) + need_for(double(surface_cells), double(grid.brick_keys.size()));
    const std::uint64_t in_use = resident_bytes();
    if (static_cast<double>(in_use) + need <= static_cast<double>(o.max_memory)) return;
    // The grid that fits: the surface (and the grid held while meshing it) shrink as the grid to
    // the power measured from this grid to the one twice as coarse, at most 2 (a dense surface).
    const auto [fine, coarser] = surface_cells_and_coarser(grid, iso);
    const double power =
        fine > 0 && coarser > 0 ? std::clamp(std::log2(double(fine) / double(coarser)), 0.25, 2.0) : 2.0;
    const double base = static_cast<double>(std::min(in_use_before_grid, in_use) + fixed);
    const double room = std::max(0.0, static_cast<double>(o.max_memory) - base);
    const double shrink = std::pow(room / std::max(1.0, static_cast<double>(in_use) + need - base), 1 / power);
    const std::uint32_t longest = std::max({grid.spec.dims[0], grid.spec.dims[1], grid.spec.dims[2]});
    const auto fit = static_cast<std::uint32_t>(std::floor(longest * std::min(0.9, 0.9 * shrink)));
    throw Error(ErrorKind::usage,
                input + ": the grid " + std::to_string(grid.spec.dims[0]) + "x" + std::to_string(grid.spec.dims[1]) +
                    "x" + std::to_string(grid.spec.dims[2]) + " does not fit: its " + std::to_string(surface_cells) +
                    " surface cells need about " + mebibytes(static_cast<std::uint64_t>(need)) +
                    " to mesh and write besides the " + mebibytes(in_use) + " in use, more than the memory limit (" +
                    mebibytes(o.max_memory) + ")" +
                    (fit > 0 ? "; a grid of " + std::to_string(fit) + " cells would fit" : "") +
                    " (nothing was written)",
                "grid", fit > 0 ? std::to_string(fit) : "");
}

// Far more points a cell than a grid chosen from the data aims at: the grid is much coarser than the points.
constexpr double too_coarse_points_per_cell = 100 * auto_grid_most_points_per_cell;

// Why the mesh came out empty, and what to try: the step that removed the last triangle, and
// whether the grid suits the points at all (the usual cause when pieces are all removed).
[[noreturn]] void empty_mesh_error(const RunReport& r, std::uint64_t fullest, std::size_t extracted) {
    std::string why, option;
    const std::string dims = std::to_string(r.grid.dims[0]) + " x " + std::to_string(r.grid.dims[1]) + " x " +
                             std::to_string(r.grid.dims[2]);
    const std::string cells = dims + " cells of " + four_digits(r.grid.cell_size);
    const bool too_coarse = double(r.median_count) > too_coarse_points_per_cell;
    const bool too_fine = r.median_count <= 1;
    if (r.points_read == r.points_outside) {
        why = "every point lies outside the grid (" + std::to_string(r.points_read) + " read, " +
              std::to_string(r.points_outside) +
              " outside the grid): scanning the points for their bounds, or bounds around them, covers them";
        option = "scan_bounds,bounds";
    } else if (extracted == 0 && !(double(fullest) > r.iso) && !(r.iso_auto && too_fine)) {
        why = "the iso " + shortest(r.iso) + " points per cell leaves no cell: the fullest holds " +
              std::to_string(fullest) + " points: try an iso below " + std::to_string(fullest) +
              " (or automatic), or a coarser grid than " + dims;
        option = "iso";
    } else if (too_coarse) {
        why = "the grid (" + cells + ") is far too coarse for these points: its " + std::to_string(r.occupied_cells) +
              " occupied cells hold a median of " + std::to_string(r.median_count) +
              " points each; give a finer grid (at most " + std::to_string(max_grid_cells) +
              " cells an axis), or bounds around each part of the data when they lie far apart";
        option = "grid";
    } else if (too_fine) {
        why = "the grid (" + cells + ") is too fine for the points' density: its occupied cells hold a median of " +
              std::to_string(r.median_count) +
              " point, so no surface holds together; give a coarser grid, or let it be chosen from the data";
        option = "grid";
    } else if (extracted == 0) {
        why = "no surface was found in the " + std::to_string(r.occupied_cells) + " occupied cells (a median of " +
              std::to_string(r.median_count) + " points each): try a coarser grid than " + dims;
        option = "grid";
    } else if (r.pieces.removed > 0 && r.pieces.triangles_removed >= extracted) {
        why = "all " + std::to_string(r.pieces.removed) + " pieces (" + std::to_string(r.pieces.triangles_removed) +
              " triangles) are smaller than the smallest piece kept, a diagonal of " + shortest(r.pieces.min_diagonal) +
              ": try a smaller one, or 0 to keep every piece";
        option = "min_piece";
    } else {
        why = "simplification removed every triangle: try a smaller bound, or 0 for none";
        option = "simplify";
    }
    throw Error(ErrorKind::input, r.input + ": the mesh is empty, nothing written: " + why, option);
}

[[noreturn]] void usage_error(const std::string& option, const std::string& what) {
    throw Error(ErrorKind::usage, what, option);
}

// A file the thin parts' second read can open again: not standard input, not a pipe.
bool readable_again(const std::string& input) {
    return input != "-" && std::filesystem::is_regular_file(input);
}

bool finite_at_least_zero(double value) {
    return std::isfinite(value) && value >= 0;
}

} // namespace

// The checks on what reading takes: inputs, options that cannot work.
void check_read_options(const std::vector<std::string>& inputs, const BuildOptions& o) {
    if (inputs.empty()) usage_error("inputs", "no input given: nothing to mesh");
    if (o.scan_bounds)
        for (const std::string& input : inputs) check_rereadable(input);
    if (o.refine_thin == ThinRefinement::always)
        for (const std::string& input : inputs)
            if (!readable_again(input))
                usage_error("refine_thin", "refining thin parts reads the inputs twice, so it needs regular files, "
                                           "not \"" +
                                               input + "\": save the stream to a file");
}

// The checks on what meshing and writing take; returns each output's format.
std::vector<MeshFormat> check_mesh_options(const std::vector<std::string>& inputs, const BuildOptions& o) {
    if (o.outputs.empty() && !o.keep_mesh) usage_error("outputs", "no output requested: nothing to do");
    if (o.refine_thin == ThinRefinement::always && o.surface != SurfaceKind::sheet)
        usage_error("refine_thin", "thin parts are refined for the sheet surface only: the closed surface wraps "
                                   "the occupied cells whatever their size");
    std::vector<MeshFormat> formats;
    for (const OutputRequest& output : o.outputs) formats.push_back(output_format(output));
    for (const OutputRequest& output : o.outputs) check_output_folder(output.path);
    if (!o.report.empty()) check_output_folder(o.report);
    std::vector<std::pair<std::string, std::string>> paths;
    for (const OutputRequest& output : o.outputs) paths.emplace_back("the output", output.path);
    if (!o.report.empty()) paths.emplace_back("the report", o.report);
    if (inputs.size() == 1) {
        paths.insert(paths.begin(), {"the input", inputs.front()});
        check_distinct_files(paths);
    } else {
        check_distinct_inputs(inputs, paths);
    }
    if (o.surface == SurfaceKind::sheet && o.placement != VertexPlacement::surface)
        usage_error("placement",
                    "vertices on the iso level are for the closed surface only: the sheet places them on the points");
    if (o.iso && !finite_at_least_zero(*o.iso))
        usage_error("iso", "the iso must be a number of points per cell, at least 0");
    if (!finite_at_least_zero(o.simplify.error))
        usage_error("simplify", "the simplification bound must be a length, at least 0");
    if (!finite_at_least_zero(o.min_piece.value) || (o.min_piece.relative && o.min_piece.value > 1))
        usage_error("min_piece", "the smallest piece must be a length, or a fraction of the mesh diagonal from 0 to 1");
    if (o.threads < 0) usage_error("threads", "the thread count must be 0 (all cores) or more");
    if (!finite_at_least_zero(o.tile_size)) usage_error("tile", "the tile size must be a length, at least 0");
    return formats;
}

namespace {

// The union of the survey's files' scanned bounds (a first pass over every record), in the
// survey's CRS. With skip_bad, a file that fails is left out of the survey, its path added to
// `left_out`.
Bounds scanned_bounds(Survey& survey, bool skip_bad, std::vector<std::string>& left_out) {
    std::optional<Bounds> all;
    for (std::size_t i = 0; i < survey.files.size();) {
        if (survey.files[i].point_count == 0) {
            ++i;
            continue;
        }
        ScanResult scan;
        try {
            scan = scan_file(survey.files[i].path);
        } catch (const Error& e) {
            if (e.kind() != ErrorKind::input) throw;
            if (!skip_bad) throw Error(e.kind(), e.what(), with_skip_option(e.option()), e.suggestion());
            left_out.push_back(survey.files[i].path);
            survey = survey_without(survey, i, e.what());
            continue;
        }
        if (scan.point_count > 0) {
            if (const auto& transform = survey.files[i].transform) { // into the survey's CRS
                const Bounds box = transform->bounds(Bounds{scan.min, scan.max});
                scan.min = box.min, scan.max = box.max;
            }
            if (!all) all = Bounds{scan.min, scan.max};
            for (int a = 0; a < 3; ++a) {
                all->min[a] = std::min(all->min[a], scan.min[a]);
                all->max[a] = std::max(all->max[a], scan.max[a]);
            }
        }
        ++i;
    }
    return all.value_or(Bounds{});
}

// A tileset's tiles span the same number of cells of their level: the root, coarsest level is
// the grid coarsened until one tile covers the survey in x and y; each finer level halves the
// cells and the tiles (a quadtree on one lattice, whose corner is the grid's). 64 cells by
// default: a tile's triangles then stay about as many at every level, and few.
constexpr std::uint32_t default_tile_cells = 64;

TilesetLattice tileset_lattice(const GridSpec& finest, double tile_size, std::size_t& levels) {
    const std::uint32_t tile_cells = finest_tile_cells(finest, tile_size);
    const std::uint32_t longest = std::max(finest.dims[0], finest.dims[1]);
    levels = 1;
    while ((std::uint64_t{tile_cells} << (levels - 1)) < longest) ++levels;
    TilesetLattice lattice;
    lattice.corner = finest.origin;
    lattice.root_edge = finest.cell_size * double(std::uint64_t{tile_cells} << (levels - 1));
    return lattice;
}

// A note for each tileset output that cannot be placed on the globe.
void add_placement_notes(const std::vector<OutputRequest>& outputs, const std::optional<CrsInfo>& crs, RunReport& r) {
    for (const OutputRequest& output : outputs)
        if (output_format(output) == MeshFormat::tileset && !(crs && crs->identified()))
            r.warnings.push_back(
                "note: " + output.path + " is not placed on the globe: " +
                (crs ? "its coordinate system is not identified" : "the input declares no coordinate system"));
}

} // namespace

std::uint32_t finest_tile_cells(const GridSpec& finest, double tile_size) {
    return tile_size > 0 ? tile_cells_for(tile_size, finest.cell_size) : default_tile_cells;
}

SurveyStart open_survey(const std::vector<std::string>& inputs, const BuildOptions& o, RunReport& r) {
    SurveyStart start;
    AccumulateOptions& accumulate = start.accumulate;
    accumulate.grid = o.grid;
    accumulate.bounds = o.bounds;
    accumulate.slice_bytes = o.slice_bytes;
    accumulate.max_memory = o.max_memory;
    // The headers first: the CRS, the frame, the bounds. One input is opened once (standard input
    // too); several each twice, header first.
    SurveyOptions survey_options;
    survey_options.skip_bad = o.skip_bad_inputs;
    survey_options.check_bounds = !o.bounds && !o.scan_bounds;
    survey_options.crs = o.crs;
    if (inputs.size() == 1) {
        if (o.scan_bounds) check_rereadable(inputs.front());
        start.single = std::make_unique<LasReader>(inputs.front());
        // An empty mesh is no use and Draco cannot encode one: say so before any device work.
        if (start.single->header().point_count == 0)
            throw_input_error(start.single->stream().name(),
                              "the header promises no point records (point count 0): nothing to mesh");
    }
    start.survey = read_survey(inputs, survey_options, start.single.get());
    Survey& survey = start.survey;
    if (o.scan_bounds && !o.bounds) accumulate.bounds = scanned_bounds(survey, o.skip_bad_inputs, start.left_out);
    if (survey.header.point_count == 0)
        throw Error(ErrorKind::input, "the headers of the " + std::to_string(survey.files.size()) +
                                          " inputs promise no point records: nothing to mesh");
    r.warnings.insert(r.warnings.end(), survey.notes.begin(), survey.notes.end());
    if (survey.crs) {
        r.crs = survey.crs_line;
        if (survey.crs->identified()) r.crs_recorded = crs_for_outputs(*survey.crs);
        if (survey.crs->unit_metres > 0) r.unit = survey.crs->unit;
    }
    return start;
}

void fit_grid_to_points(CellGrid& grid, const BuildOptions& o, std::vector<std::string>& notes) {
    if (o.iso && *o.iso < 1) return;
    const std::string asked = std::to_string(grid.spec.dims[0]) + " x " + std::to_string(grid.spec.dims[1]) + " x " +
                              std::to_string(grid.spec.dims[2]);
    const int merged = coarsen_while_single_points(grid);
    if (merged == 0) return;
    const std::string times = std::to_string(1 << merged) + " times coarser";
    grid.grid_reason += (grid.grid_reason.empty() ? "" : "; ") + times + " than the " + asked + " asked for, too fine";
    notes.push_back("note: the grid asked for, " + asked +
                    " cells, is too fine for these points: more than half of its occupied cells held a single point, "
                    "which no surface goes through; meshed " +
                    times + ", where they hold a median of " + std::to_string(grid.median_count()));
}

CellFacts cell_facts(const CellGrid& grid) {
    return {grid.occupied_cells(), grid.fullest_cell(), grid.median_count(), grid.host_bytes()};
}

void report_grid(const CellGrid& grid, const CellFacts& facts, const Survey& survey,
                 const std::vector<std::string>& reader_warnings, bool note_outputs, const BuildOptions& o,
                 double seconds, BuildObserver& watch, Accumulation& a, RunReport& r) {
    r.warnings.insert(r.warnings.end(), reader_warnings.begin(), reader_warnings.end());
    r.input_files = survey.files.size();
    for (const SkippedInput& skipped : survey.skipped) r.skipped_inputs.push_back(skipped.reason);
    r.grid_reason = grid.grid_reason;
    r.read_accumulate = seconds;
    r.points_read = grid.points_read, r.points_outside = grid.points_outside, r.grid = grid.spec;
    a.fullest_cell = facts.fullest; // for the message should the mesh come out empty
    r.occupied_cells = facts.occupied;
    r.median_count = facts.median;
    r.occupied_bricks = grid.brick_keys.size();
    r.pool_bytes = r.occupied_bricks * brick_device_bytes(grid.has_color());
    r.host_grid_bytes = facts.host_bytes;
    if (has_color(survey.header) && !grid.has_color())
        r.warnings.push_back("note: " + r.input + ": the colour of every point is 0 (black): the mesh has no colour");
    if (double(r.median_count) > too_coarse_points_per_cell)
        r.warnings.push_back("warning: the grid (" + std::to_string(r.grid.dims[0]) + " x " +
                             std::to_string(r.grid.dims[1]) + " x " + std::to_string(r.grid.dims[2]) + " cells of " +
                             four_digits(r.grid.cell_size) + ") is far too coarse for these points: its " +
                             std::to_string(r.occupied_cells) + " occupied cells hold a median of " +
                             std::to_string(r.median_count) +
                             " points each; a finer grid, or bounds around each part of the data, resolves them");
    if (note_outputs) add_placement_notes(o.outputs, survey.crs, r); // said with the read's notes
    watch.stage_ended(BuildStage::read_accumulate, r);
    watch.detail("accumulated    " + std::to_string(grid.points_read) + " points into " + megabytes(r.pool_bytes) +
                 " of bricks in " + two_digits(r.read_accumulate) + " s");
    a.crs = survey.crs;
}

std::string reading_line(const SurveyReader& reader, bool single_untransformed) {
    const LasHeader& header = reader.header();
    if (single_untransformed)
        return "reading        " + reader.name() + ": LAS " + version_string(header) + ", point format " +
               std::to_string(header.point_format) + ", " + std::to_string(header.point_count) + " points promised";
    return "reading        " + reader.name() + ": " + std::to_string(header.point_count) +
           " points promised, in point format " + std::to_string(header.point_format) + ", scale " +
           shortest(header.scale[0]) + " " + shortest(header.scale[1]) + " " + shortest(header.scale[2]) + ", offset " +
           shortest(header.offset[0]) + " " + shortest(header.offset[1]) + " " + shortest(header.offset[2]);
}

std::string device_line(const ComputeDevice& device) {
    return "device         " + device.info().name + " (" + device.info().platform + "), " +
           megabytes(device.info().global_memory) + " memory, largest buffer " + megabytes(device.info().max_alloc);
}

// Reads the inputs and sums their points into `a.grid`; fills the read's fields of `r`, with
// the outputs' placement notes when `note_outputs`.
void accumulate_survey(const std::vector<std::string>& inputs, const BuildOptions& o, bool note_outputs,
                       BuildObserver& watch, Accumulation& a, RunReport& r) {
    const auto start = std::chrono::steady_clock::now();
    SurveyStart opened = open_survey(inputs, o, r);
    Survey& survey = opened.survey;
    AccumulateOptions& accumulate = opened.accumulate;
    LasReader* single = opened.single.get();
    ComputeDevice device(o.device);
    r.device = device.info().name;
    accumulate.memory_in_use = resident_bytes(); // the program, its libraries, the OpenCL runtime
    a.memory_in_use = accumulate.memory_in_use;
    CellGrid& grid = a.grid;
    a.left_out = opened.left_out;
    std::vector<std::string> reader_warnings;
    for (;;) { // once, or again without a file that failed part-way (skip_bad_inputs)
        SurveyReader reader(survey, single);
        const LasHeader& header = reader.header();
        r.input = reader.name();
        watch.stage_started(BuildStage::read_accumulate, "reading " + r.input);
        watch.detail(reading_line(reader, single && !survey.files.front().transform));
        watch.detail(device_line(device));
        accumulate.on_slice = [&](std::uint64_t points) {
            watch.points_read(points, header.point_count, reader.bytes_read(), reader.bytes_total());
        };
        try {
            grid = accumulate_cells(reader, device, accumulate);
        } catch (const Error& e) {
            if (single || e.kind() != ErrorKind::input || !reader.failed_file()) throw;
            if (!o.skip_bad_inputs) throw Error(e.kind(), e.what(), with_skip_option(e.option()), e.suggestion());
            a.left_out.push_back(survey.files[*reader.failed_file()].path);
            survey = survey_without(survey, *reader.failed_file(), e.what());
            if (o.scan_bounds && !o.bounds) accumulate.bounds = scanned_bounds(survey, o.skip_bad_inputs, a.left_out);
            continue;
        }
        reader_warnings = reader.warnings();
        break;
    }
    fit_grid_to_points(grid, o, reader_warnings);
    report_grid(grid, cell_facts(grid), survey, reader_warnings, note_outputs, o, seconds_since(start), watch, a, r);
}

bool refines_thin_parts(const std::vector<std::string>& inputs, const BuildOptions& o, std::uint64_t median,
                        RunReport& r) {
    if (o.refine_thin != ThinRefinement::automatic) return o.refine_thin == ThinRefinement::always;
    if (o.surface != SurfaceKind::sheet) {
        r.thin_unrefined = "the closed surface wraps the occupied cells whatever their size";
        return false;
    }
    if (o.grid.kind != GridRequest::Kind::automatic) {
        r.thin_unrefined = "a grid was asked for: its cell everywhere, unless thin parts are asked to be refined";
        return false;
    }
    for (const std::string& input : inputs)
        if (!readable_again(input)) {
            r.thin_unrefined = (input == "-" ? std::string("standard input") : "\"" + input + "\"") +
                               " cannot be read twice: save it to a file to refine them";
            return false;
        }
    if (median < thin_parts_min_median) {
        r.thin_unrefined = "the points are too sparse for half cells (a median of " + std::to_string(median) +
                           " in an occupied cell, " + std::to_string(thin_parts_min_median) + " needed)";
        return false;
    }
    return true;
}

namespace {

// What a step run in another thread tells its observer, kept for the calling thread to pass on
// (BuildObserver's calls come from the calling thread only): the stages it starts and its detail
// lines, which is all the second read tells. Its progress through the points is not kept: it
// ran behind another stage.
struct RecordedObserver : BuildObserver {
    std::vector<std::pair<std::optional<BuildStage>, std::string>> told; // a stage started, or a detail line
    void stage_started(BuildStage stage, const std::string& what) override { told.emplace_back(stage, what); }
    void detail(const std::string& line) override { told.emplace_back(std::nullopt, line); }
    void replay(BuildObserver& watch) const {
        for (const auto& [stage, text] : told)
            if (stage)
                watch.stage_started(*stage, text);
            else
                watch.detail(text);
    }
};

} // namespace

// The second read's largest upload to the device when the options leave it open.
constexpr std::uint64_t thin_read_slice_bytes = 4ull << 20;

// The second read's grid of half the cell spans the whole survey, and its brick index a word
// for every brick of that volume: at 4,096 cells an axis at most (a 4 GB index for a cube), the
// thin parts of larger grids are not refined rather than the run stopped for want of memory.
constexpr std::uint32_t max_thin_grid_cells = 4096;

std::optional<ThinReadPlan> plan_thin_read(const BuildOptions& o, const CellGrid& grid, RunReport& r) {
    return plan_thin_read(thin_cells(grid, o.iso ? *o.iso : automatic_iso(grid)), grid.spec, grid.axes, r);
}

std::optional<ThinReadPlan> plan_thin_read(const std::vector<std::array<std::int64_t, 3>>& thin_at,
                                           const GridSpec& spec, const std::array<AxisCells, 3>& axes, RunReport& r) {
    ThinReadPlan plan;
    if (thin_at.empty()) {
        r.thin_unrefined = "no thin parts found";
        return std::nullopt;
    }
    for (const std::uint32_t d : spec.dims)
        if (std::uint64_t{d} * 2 > max_thin_grid_cells) {
            r.thin_unrefined =
                "half the cell would take more than " + std::to_string(max_thin_grid_cells) + " cells an axis";
            return std::nullopt;
        }
    const std::array<std::int64_t, 3> dims{spec.dims[0], spec.dims[1], spec.dims[2]};
    plan.mesh_cells = blocks_around(thin_at, dims, 0, thin_mesh_reach);
    plan.read_cells = blocks_around(thin_at, dims, 0, thin_read_reach);
    plan.spec = spec;
    plan.axes = axes;
    return plan;
}

Refinement read_thin_parts(const ThinReadPlan& plan, const std::vector<std::string>& inputs,
                           const std::vector<std::string>& left_out, const BuildOptions& o, BuildObserver& watch,
                           RunReport& r) {
    const auto start = std::chrono::steady_clock::now();
    Refinement refined;
    refined.cells = plan.mesh_cells;
    r.thin_cells = refined.cells.size();
    const GridSpec& spec = plan.spec;
    RunReport again; // the first read reported the survey's notes
    // The fine grid is fixed (below): with scanned bounds, the records are not scanned a third
    // time (the files the scan left out are in `left_out`); any bounds stop the headers' check.
    BuildOptions read_again = o;
    if (read_again.scan_bounds && !read_again.bounds) {
        read_again.scan_bounds = false;
        Bounds box{spec.origin, spec.origin};
        for (int a = 0; a < 3; ++a) box.max[a] += spec.cell_size * spec.dims[a];
        read_again.bounds = box;
    }
    SurveyStart opened = open_survey(inputs, read_again, again);
    for (const std::string& path : left_out)
        for (std::size_t i = 0; i < opened.survey.files.size(); ++i)
            if (opened.survey.files[i].path == path) {
                opened.survey = survey_without(opened.survey, i, "left out by the first read");
                break;
            }
    AccumulateOptions accumulate = opened.accumulate;
    GridSpec fine = spec;
    fine.cell_size /= 2; // exact: the fine cells split the grid's cells in two on every axis
    for (std::uint32_t& d : fine.dims) d *= 2;
    accumulate.spec = fine;
    accumulate.memory_in_use = resident_bytes();
    // Smaller slices than the first read's: this read mostly runs while the grid is extracted,
    // so its memory adds to the extraction's (4 MiB measured as fast as 16 on the deck).
    if (!o.slice_bytes) accumulate.slice_bytes = thin_read_slice_bytes;
    // Only the points of the cells near the thin parts reach the device (most points lie far
    // from any); the survey's frame has the raw integers the grid's cell starts are in.
    const CellSet near_cells(plan.read_cells, {spec.dims[0], spec.dims[1], spec.dims[2]});
    const RecordsInCells near_thin(plan.axes, near_cells, opened.survey.header.point_record_length);
    SurveyReader reader(opened.survey, opened.single.get());
    reader.on_records(
        [&](std::size_t, std::byte* records, std::size_t count) { return near_thin.keep(records, count); });
    watch.stage_started(BuildStage::read_accumulate, "reading the thin parts again");
    ComputeDevice device(o.device);
    refined.fine = accumulate_cells(reader, device, accumulate);
    r.thin_read = seconds_since(start);
    watch.detail("thin parts     " + std::to_string(plan.read_cells.size()) + " cells read again at cells of " +
                 four_digits(fine.cell_size) + ": " + std::to_string(refined.fine.occupied_cells()) +
                 " occupied cells, in " + two_digits(r.thin_read) + " s");
    return refined;
}

Mesh thin_parts_mesh(const Refinement& refined, double iso, bool iso_auto, const GridSpec& grid,
                     const std::function<const SeamCorners&()>& coarse_seam) {
    // A quarter of the iso: the same points per area in cells of half the edge; an automatic one
    // rounded as automatic_iso rounds (not the finer grid's own median, which would follow how
    // far around the thin parts its points were read).
    const double fine_iso = iso_auto ? std::max(1.0, std::floor(iso / 4)) : iso / 4;
    Mesh thin = extract_sheet(refined.fine, fine_iso, LinearParts::tubes, coarse_seam);
    keep_triangles_in_blocks(thin, grid, 0, refined.cells, true);
    return thin;
}

std::optional<Refinement> refine_thin_parts(const std::vector<std::string>& inputs,
                                            const std::vector<std::string>& left_out, const BuildOptions& o,
                                            const CellGrid& grid, BuildObserver& watch, RunReport& r) {
    const std::optional<ThinReadPlan> plan = plan_thin_read(o, grid, r);
    if (!plan) return std::nullopt;
    return read_thin_parts(*plan, inputs, left_out, o, watch, r);
}

namespace {

// The detail line of how the thin parts' mesh joined the sheet.
std::string seam_line(const SeamReport& seam) {
    return "seam           " + four_digits(seam.open_after) + " of " + four_digits(seam.open_before) +
           " of border left open where the two meshes meet (" + std::to_string(seam.joined) + " stretches joined)";
}

} // namespace

// Extracts the mesh of `grid` (the accumulation's, or a copy of it) and writes every output;
// `r` holds the read's fields, `seconds_before` the time the read took.
BuildResult mesh_grid(CellGrid&& grid, const Accumulation& a, RunReport r, const std::vector<std::string>& inputs,
                      const BuildOptions& o, const std::vector<MeshFormat>& formats, BuildObserver& watch,
                      double seconds_before, const Refinement* refined, const ThinReadPlan* thin_read,
                      GridInTiles* in_tiles) {
    const auto mesh_start = std::chrono::steady_clock::now();
    BuildResult result;
    // Under a memory limit the second read comes first, alone: each step's check of the memory
    // it will take counts on the others' being done. With one thread asked for, too.
    std::optional<Refinement> read_first;
    if (thin_read && (o.max_memory || o.threads == 1)) {
        read_first = read_thin_parts(*thin_read, inputs, a.left_out, o, watch, r);
        r.read_accumulate += r.thin_read;
        refined = &*read_first, thin_read = nullptr;
    }
    if (in_tiles && in_tiles->refined) refined = &*in_tiles->refined;
    const bool thin_refined = refined || thin_read;
    watch.stage_started(BuildStage::extract, "extracting the surface");
    const auto extract_start = std::chrono::steady_clock::now();
    r.iso_auto = !o.iso;
    r.iso = in_tiles ? in_tiles->iso : o.iso ? *o.iso : automatic_iso(grid);
    if (o.max_memory && !in_tiles) check_extraction_memory(grid, r.iso, o, formats, r.input, a.memory_in_use);
    r.surface = o.surface;
    r.placement = o.placement;
    // A tileset's coarser levels, coarsest first: the grid's cells merged 2 x 2 x 2, exactly.
    const bool tileset = std::find(formats.begin(), formats.end(), MeshFormat::tileset) != formats.end();
    std::size_t level_count = 1;
    TilesetLattice lattice;
    std::vector<CellGrid> coarser;
    if (tileset) {
        lattice = tileset_lattice(grid.spec, o.tile_size, level_count);
        for (std::size_t k = 1; k < level_count; ++k)
            coarser.insert(coarser.begin(), k > 1      ? coarsen_grid(coarser.front())
                                            : in_tiles ? std::move(in_tiles->coarser)
                                                       : coarsen_grid(grid));
    }
    const std::uint32_t tile_order =
        tileset && o.surface == SurfaceKind::sheet ? finest_tile_cells(grid.spec, o.tile_size) : 0;
    // Extraction, small pieces, simplification and normals: the mesh of one grid.
    const auto surface_of = [&](CellGrid&& cells, double iso, PieceCount* pieces, SimplifyReport* simplified) {
        const double cell = cells.spec.cell_size;
        const GridSpec spec = cells.spec;
        std::shared_ptr<const Accumulation::Surface> kept; // the finest level's, when it has the same options
        if (pieces && a.keeps_surface) {
            const std::lock_guard lock(a.surface_mutex);
            if (a.surface && a.surface->same_options(iso, o, thin_refined, tile_order)) kept = a.surface;
        }
        Mesh m;
        std::size_t extracted = 0;
        PieceCount removed;
        if (kept) {
            m = kept->mesh, extracted = kept->extracted, removed = kept->pieces;
            cells = CellGrid{};
            watch.detail("extracted      " + std::to_string(extracted) + " triangles at iso " + four_digits(iso) +
                         ", the accumulation's surface re-used");
        } else {
            if (in_tiles && pieces) { // the tiles' sheet, the thin parts joined to it
                TiledFinest finest = finest_sheet_in_tiles(spec, in_tiles->windows, in_tiles->part_of, iso, r.iso_auto,
                                                           in_tiles->survey, refined);
                m = std::move(finest.mesh);
#ifdef __GLIBC__
                // The tiles' parts, planes and sheets were freed into glibc's arenas, which keep
                // them: given back now, they do not stay resident beside the simplification (the
                // 20M deck's merge in 32 tiles peaked at 487 MB without, 381-414 MB with).
                malloc_trim(0);
#endif
                watch.detail("tiles          the sheet meshed in " + std::to_string(in_tiles->windows.size()) +
                             " tiles, each from its tile's file and its neighbours'");
                if (finest.seam) watch.detail(seam_line(*finest.seam));
            } else {
                // The second read of the thin parts and their mesh are made in a thread of their own
                // while the grid is extracted, from the moment the grid's cells are released (their
                // memory and the read's never add up): the two take about as long, and each leaves
                // cores idle (the read waits on the input and the device, the extraction has serial
                // steps). The read tells a recorder, replayed to the observer here once it is joined:
                // the observer hears only from the calling thread, in order.
                // The fine sheet ends on the refined cells' faces where this sheet does: it waits for
                // this sheet's samples at their corners, made before this sheet is marched.
                const std::vector<std::uint64_t>* seam_cells = !pieces     ? nullptr
                                                               : thin_read ? &thin_read->mesh_cells
                                                               : refined   ? &refined->cells
                                                                           : nullptr;
                std::shared_future<SeamCorners> seam_corners;    // before `thin_mesh`: the read may wait on it
                std::function<const SeamCorners&()> coarse_seam; // set once they are asked for
                RunReport read_report;       // before `thin_mesh`, whose end the unwinding waits for
                RecordedObserver read_told;  // the same
                std::future<Mesh> thin_mesh; // from std::async: its destructor waits for the read
                // After `thin_mesh`: on unwinding it goes first, so a read waiting on it wakes (to a
                // broken promise) before thin_mesh's destructor waits for that read.
                std::promise<SeamCorners> seam_sampled;
                seam_corners = seam_sampled.get_future().share();
                const auto start_reading = [&] {
                    if (thin_read && pieces)
                        thin_mesh = std::async(std::launch::async, [&] {
                            const Refinement read =
                                read_thin_parts(*thin_read, inputs, a.left_out, o, read_told, read_report);
                            return thin_parts_mesh(read, iso, r.iso_auto, spec, coarse_seam);
                        });
                };
                // The sheet releases the grid's cells as soon as it no longer reads them; the closed
                // surface holds them to the end (and is never refined: check_mesh_options).
                if (o.surface == SurfaceKind::sheet) {
                    std::optional<SeamRequest> seam;
                    bool handed = false;
                    if (seam_cells) {
                        seam =
                            SeamRequest{seam_corners_of(*seam_cells, {spec.dims[0], spec.dims[1], spec.dims[2]}),
                                        [&](SeamCorners&& c) { seam_sampled.set_value(std::move(c)), handed = true; }};
                        coarse_seam = [&]() -> const SeamCorners& { return seam_corners.get(); };
                    }
                    m = extract_sheet(std::move(cells), iso, LinearParts::planes, start_reading,
                                      seam ? &*seam : nullptr);
                    // A tileset's finest sheet in its tiles' order: the mesh a merge meshing it tile
                    // by tile makes, so the two write the same bytes.
                    if (tile_order > 0 && pieces) m = in_tile_order(std::move(m), spec, tile_order);
                    // A sheet that returned without sampling them must not leave the read waiting.
                    if (seam && !handed)
                        seam_sampled.set_exception(std::make_exception_ptr(
                            std::logic_error("the coarse sheet gave no samples on the seam's faces")));
                } else {
                    m = extract_closed_surface(cells, iso, o.placement);
                    start_reading();
                }
                // The cells near thin parts from the finer grid, the rest from this one.
                if (thin_mesh.valid() || (refined && pieces)) {
                    const bool read_now = thin_mesh.valid();
                    const Mesh thin =
                        read_now ? thin_mesh.get() : thin_parts_mesh(*refined, iso, r.iso_auto, spec, coarse_seam);
                    if (read_now) {
                        r.thin_cells = read_report.thin_cells, r.thin_read = read_report.thin_read;
                        read_told.replay(watch);
#ifdef __GLIBC__
                        // The read's thread freed its grids into a malloc arena of its own, which
                        // glibc keeps: given back now, they do not stay resident beside the growing
                        // mesh (the merge of the 50M deck's 21 tiles peaked at 400 MB instead of 430).
                        malloc_trim(0);
#endif
                    }
                    const std::vector<std::uint64_t>& fine_cells = read_now ? thin_read->mesh_cells : refined->cells;
                    keep_triangles_in_blocks(m, spec, 0, fine_cells, false);
                    watch.detail(seam_line(append_joined(m, thin, spec, fine_cells)));
                }
            }
            cells = CellGrid{}; // not needed any more: the writers get its memory
            extracted = m.triangles.size();
            if (pieces)
                watch.detail("extracted      " + std::to_string(extracted) + " triangles at iso " + four_digits(iso));
            if (pieces) watch.stage_started(BuildStage::extract, "removing small pieces");
            removed = remove_small_pieces(m, o.min_piece);
            if (pieces && a.keeps_surface) {
                auto surface = std::make_shared<const Accumulation::Surface>(Accumulation::Surface{
                    iso, o.surface, o.placement, o.min_piece, thin_refined, tile_order, extracted, removed, m});
                const std::lock_guard lock(a.surface_mutex);
                a.surface = std::move(surface);
            }
        }
        SimplifyOptions simplify;
        simplify.error = o.simplify.in_cells ? o.simplify.error * cell : o.simplify.error;
        simplify.lock_border = o.simplify.lock_border;
        if (pieces && simplify.error > 0)
            watch.stage_started(BuildStage::extract,
                                "simplifying " + std::to_string(m.triangles.size()) + " triangles");
        const SimplifyReport report = simplify_mesh(m, simplify);
        if (pieces && simplify.error > 0)
            watch.detail("simplified     " + std::to_string(report.triangles_before) + " to " +
                         std::to_string(report.triangles_after) + " triangles within " + four_digits(simplify.error) +
                         " in " + two_digits(report.seconds) + " s");
        if (pieces) *pieces = removed;
        if (simplified) *simplified = report;
        if (pieces && m.triangles.empty()) empty_mesh_error(r, a.fullest_cell, extracted);
        if (!o.normals)
            m.normals.clear();
        else if (m.normals.empty()) {
            if (pieces) watch.stage_started(BuildStage::extract, "computing normals");
            compute_vertex_normals(m); // the extraction gave none
        }
        m.crs = r.crs_recorded;
        return m;
    };
    Mesh mesh = surface_of(std::move(grid), r.iso, &r.pieces, &r.simplify);
    // The coarser levels of a tileset, each measured against the finest.
    std::vector<Mesh> coarse_meshes; // reserved: levels point into it
    coarse_meshes.reserve(coarser.size());
    std::vector<TilesetLevel> levels;
    std::optional<FinestLevel> finest;
    if (!coarser.empty()) finest.emplace(mesh);
    for (std::size_t k = 0; k < coarser.size(); ++k) {
        watch.stage_started(BuildStage::extract, "level " + std::to_string(k) + " of the tileset");
        const double scale = std::ldexp(1.0, 2 * static_cast<int>(coarser.size() - k)); // points per surface cell
        const double iso = r.iso_auto ? automatic_iso(coarser[k]) : r.iso * scale;
        const auto level_start = std::chrono::steady_clock::now();
        coarse_meshes.push_back(surface_of(std::move(coarser[k]), iso, nullptr, nullptr));
        finest->remove_far(coarse_meshes.back(), 2 * coarse_meshes.back().cell_size);
        const double error = finest->error(coarse_meshes.back());
        watch.detail("level " + std::to_string(k) + "        " + std::to_string(coarse_meshes.back().triangles.size()) +
                     " triangles, cells of " + four_digits(coarse_meshes.back().cell_size) + ", " + four_digits(error) +
                     " from the finest, in " + two_digits(seconds_since(level_start)) + " s");
        levels.push_back({&coarse_meshes.back(), error});
    }
    levels.push_back({&mesh, 0});
    r.extract = seconds_since(extract_start);
    r.vertices = mesh.positions.size(), r.triangles = mesh.triangles.size(), r.colored = !mesh.colors.empty();
    r.normals = !mesh.normals.empty();
    r.origin = mesh.origin;
    watch.stage_ended(BuildStage::extract, r);

    // Every output into its temporary file first, then all renamed: all of them or none.
    const auto write_start = std::chrono::steady_clock::now();
    std::vector<std::unique_ptr<OutputFile>> files;
    std::optional<WrittenTileset> tiles;
    std::string tileset_path;
    for (std::size_t i = 0; i < o.outputs.size(); ++i) {
        const OutputRequest& output = o.outputs[i];
        watch.stage_started(BuildStage::write, "writing " + output.path);
        const auto output_start = std::chrono::steady_clock::now();
        files.push_back(std::make_unique<OutputFile>(output.path));
        std::uint64_t bytes = 0;
        if (formats[i] == MeshFormat::tileset) {
            TilesetContent content;
            content.glb = {output.glb_compression, GltfOrigin::extras, "tile", output.draco};
            content.crs = a.crs;
            tiles = write_tileset(levels, lattice, content, *files.back());
            tileset_path = output.path;
            bytes = tiles->content_bytes;
        } else {
            // Named after the input, or with several after the output: never after one input of many.
            const std::string name = mesh_name(inputs.size() == 1 ? inputs.front() : output.path);
            write_mesh_into(mesh, output, formats[i], name, *files.back(),
                            formats[i] == MeshFormat::html ? run_report_json(r) : std::string());
        }
        files.back()->finish();
        r.outputs.push_back({output.path, bytes + files.back()->bytes(), seconds_since(output_start)});
        watch.detail("wrote          " + output.path + " in " + two_digits(r.outputs.back().seconds) + " s");
    }
    r.write = seconds_since(write_start);
    r.total = seconds_before + seconds_since(mesh_start);
    r.peak_rss_bytes = peak_rss_bytes();
    if (!o.report.empty()) { // renamed with the meshes: the report of a run whose outputs exist
        files.push_back(std::make_unique<OutputFile>(o.report));
        files.back()->write(run_report_json(r));
    }
    try {
        commit_all(files);
    } catch (const Error&) {
        std::error_code ignored; // the tiles of a tileset that did not appear
        if (tiles && tiles->folder_created)
            std::filesystem::remove_all(std::filesystem::path(tileset_path).parent_path() / tiles->folder, ignored);
        throw;
    }
    if (tiles) remove_earlier_tiles(tileset_path, tiles->folder);
    watch.stage_ended(BuildStage::write, r);
    result.report = std::move(r);
    if (o.keep_mesh) result.mesh = std::move(mesh);
    return result;
}

namespace {

// Whether two BuildOptions read the same: the fields accumulate_inputs takes.
bool same_read_options(const BuildOptions& a, const BuildOptions& b) {
    const auto bounds_key = [](const std::optional<Bounds>& x) {
        return x ? std::make_tuple(true, x->min, x->max) : std::make_tuple(false, Vec3{}, Vec3{});
    };
    return a.grid.kind == b.grid.kind && a.grid.dims == b.grid.dims && a.grid.voxel == b.grid.voxel &&
           bounds_key(a.bounds) == bounds_key(b.bounds) && a.scan_bounds == b.scan_bounds &&
           a.skip_bad_inputs == b.skip_bad_inputs && a.crs == b.crs && a.device == b.device &&
           a.slice_bytes == b.slice_bytes && a.max_memory == b.max_memory;
}

} // namespace

BuildResult build_mesh(const std::string& input, const BuildOptions& o, BuildObserver* observer) {
    return build_mesh(std::vector<std::string>{input}, o, observer);
}

BuildResult build_mesh(const std::vector<std::string>& inputs, const BuildOptions& o, BuildObserver* observer) {
    BuildObserver silent;
    BuildObserver& watch = observer ? *observer : silent;
    check_read_options(inputs, o);
    const std::vector<MeshFormat> formats = check_mesh_options(inputs, o); // before reading
    std::optional<tbb::global_control> thread_limit;
    if (o.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, o.threads);
    const auto start = std::chrono::steady_clock::now();
    Accumulation a;
    RunReport r;
    accumulate_survey(inputs, o, true, watch, a, r);
    std::optional<ThinReadPlan> thin_read;
    if (refines_thin_parts(inputs, o, a.grid.median_count(), r)) thin_read = plan_thin_read(o, a.grid, r);
    return mesh_grid(std::move(a.grid), a, std::move(r), inputs, o, formats, watch, seconds_since(start), nullptr,
                     thin_read ? &*thin_read : nullptr);
}

AccumulatedInputs accumulate_inputs(const std::vector<std::string>& inputs, const BuildOptions& o,
                                    BuildObserver* observer) {
    BuildObserver silent;
    check_read_options(inputs, o);
    auto a = std::make_shared<Accumulation>();
    a->read_options = o;
    a->keeps_surface = true;
    AccumulatedInputs result;
    result.inputs = inputs;
    accumulate_survey(inputs, o, false, observer ? *observer : silent, *a, result.report);
    result.accumulation = std::move(a);
    return result;
}

BuildResult build_mesh(const AccumulatedInputs& accumulated, const BuildOptions& o, BuildObserver* observer) {
    BuildObserver silent;
    if (!accumulated.accumulation) usage_error("inputs", "nothing accumulated: accumulate_inputs first");
    const Accumulation& a = *accumulated.accumulation;
    if (!same_read_options(a.read_options, o))
        usage_error("grid", "these options read the inputs differently (grid, bounds, CRS, device or memory) from "
                            "the accumulation they are meant to mesh: accumulate the inputs again with them");
    if (o.refine_thin == ThinRefinement::always) check_read_options(accumulated.inputs, o); // files, read again
    const std::vector<MeshFormat> formats = check_mesh_options(accumulated.inputs, o);
    BuildObserver& watch = observer ? *observer : silent;
    std::optional<tbb::global_control> thread_limit;
    if (o.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, o.threads);
    RunReport r = accumulated.report;
    add_placement_notes(o.outputs, a.crs, r);
    // The thin parts: those read for this iso already, else read now and kept for the next mesh.
    std::shared_ptr<const Accumulation::ThinParts> thin;
    if (refines_thin_parts(accumulated.inputs, o, a.grid.median_count(), r)) {
        const double iso = o.iso ? *o.iso : automatic_iso(a.grid);
        {
            const std::lock_guard lock(a.surface_mutex);
            if (a.thin_parts && a.thin_parts->iso == iso) thin = a.thin_parts;
        }
        if (!thin) {
            RunReport read;
            auto parts = std::make_shared<Accumulation::ThinParts>();
            parts->iso = iso;
            parts->refinement = refine_thin_parts(accumulated.inputs, a.left_out, o, a.grid, watch, read);
            parts->cells = read.thin_cells, parts->read_seconds = read.thin_read,
            parts->unrefined = read.thin_unrefined;
            r.read_accumulate += read.thin_read;
            thin = parts;
            const std::lock_guard lock(a.surface_mutex);
            a.thin_parts = std::move(parts);
        }
        r.thin_cells = thin->cells, r.thin_read = thin->read_seconds, r.thin_unrefined = thin->unrefined;
    }
    CellGrid grid = a.grid; // the accumulation stays whole for the next mesh
    const double seconds_before = r.read_accumulate;
    return mesh_grid(std::move(grid), a, std::move(r), accumulated.inputs, o, formats, watch, seconds_before,
                     thin && thin->refinement ? &*thin->refinement : nullptr);
}

} // namespace lasmesh
