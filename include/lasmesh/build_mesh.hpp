// SPDX-License-Identifier: Apache-2.0
// lasmesh as one library call: a LAS point cloud in, a coloured triangle mesh with normals out.
//
//     lasmesh::BuildOptions options;                  // the command line's defaults: grid from the data, ...
//     options.outputs.push_back({"deck.glb"});        // the format from the extension
//     try {
//         lasmesh::BuildResult result = lasmesh::build_mesh("deck.las", options);
//         std::cout << result.report.triangles << " triangles\n";
//     } catch (const lasmesh::Error& e) {              // bad input, options, device or output
//         std::cerr << e.what() << "\n";
//     }
//
// BuildOptions{} meshes exactly as `lasmesh deck.las -o deck.glb` does, byte for byte; set a
// field to do what its flag does (options.grid = lasmesh::GridRequest::longest(512) is --grid 512).
//
// The stages, in order, each in its own folder of src/ and include/lasmesh/:
//   read     the input stream (file, pipe, gzip/bzip2/xz/zstd), the LAS header, the records
//   grid     the points counted into a sparse grid of cubic cells on an OpenCL device: per cell
//            the count and the sums of colours and positions; where the points are denser than
//            the automatic grid, those near thin parts counted again at half the cell
//            (ThinRefinement)
//   mesh     one sheet through the points of each surface (or a closed surface), then small
//            isolated pieces removed, then the mesh simplified to an error bound (when asked),
//            then vertex normals (where the extraction gave none)
//   io       each requested output written (PLY, Draco, glTF) to a temporary file; all renamed
//            into place at the end, so either every output appears or none does
// The same run spread over many machines (plan_tiles, run_tile, merge_tiles) is at the end.
// An empty mesh is an error (ErrorKind::input) saying which step removed what and what to try.
// Every failure is an Error with its kind (see error.hpp); nothing is written to a stream:
// progress and details go to the BuildObserver, numbers to the RunReport.
#pragma once

#include "lasmesh/error.hpp"
#include "lasmesh/grid.hpp"
#include "lasmesh/mesh.hpp"
#include "lasmesh/mesh_files.hpp"
#include "lasmesh/mesh_pieces.hpp"
#include "lasmesh/simplify.hpp"
#include "lasmesh/surface.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lasmesh {

// Thin parts (rails, posts, cables: thinner than about a cell in two directions) meshed again at
// half the cell, from a second read of the points near them; the sheet only.
//   automatic  with the grid chosen from the data (GridRequest{}) when the points are denser than
//              it: the occupied cells hold a median of at least 12 points (a surface cell of half
//              the size then holds about 3, the fewest a plane or a tube through them needs;
//              sparse aerial data fits worse refined), as where the automatic grid reaches its
//              1024 cells an axis; and every input is a file (standard input cannot be read
//              twice). A grid asked for is meshed at its cell. Otherwise the report's
//              thin_unrefined says why not.
//   always     whatever the grid and density; an Error (usage) for standard input or the closed
//              surface.
//   never      one cell size everywhere.
enum class ThinRefinement { automatic, always, never };

// How far simplification may move the surface: a length in the file's units, or in cells.
struct SimplifyRequest {
    // Default: half a cell. On the 5M-point deck's sheets it keeps 1/5 (grid 1024) to 1/8
    // (grid 512) of the triangles while the cloud-to-mesh distances grow by less than 0.01 cell,
    // with no face turned over (docs/benchmarks.md). 0: no simplification.
    double error = 0.5;
    bool in_cells = true;     // `error` counts grid cells (0.5: half a cell)
    bool lock_border = false; // open borders stay where they are (tile seams)
};

struct BuildOptions {
    GridRequest grid;             // default: chosen from the data; or GridRequest::longest(N), cells(...), cell_edge(E)
    std::optional<Bounds> bounds; // the region to grid; default: the header bounds
    bool scan_bounds = false;     // read the inputs twice, first for their points' real bounds
    // Several inputs: leave out an input that cannot be read (listed in the report) instead of
    // stopping. One that fails part-way through its points costs a second read of the others.
    bool skip_bad_inputs = false;
    // The CRS to mesh in: "EPSG:32631" or a WKT; inputs in other CRSs are transformed with PROJ.
    // Default: the CRS most inputs declare, projected to the UTM zone of the data's centre when
    // it is longitude and latitude (cells must be cubes in one unit).
    std::string crs;
    std::optional<double>
        iso; // points per cell at the surface; default: a tenth of the occupied cells' median count, at least 1
    SurfaceKind surface = SurfaceKind::sheet;
    VertexPlacement placement = VertexPlacement::surface; // closed surfaces only
    MinPiece min_piece;                                   // default: 5% of the mesh diagonal
    SimplifyRequest simplify;                             // default: half a cell (see SimplifyRequest)
    bool normals = true;                                  // per-vertex normals in every output
    // Thin parts meshed again at half the cell: by default where the points are dense enough.
    ThinRefinement refine_thin = ThinRefinement::automatic;
    std::string device = "auto";   // "auto" (a GPU if any), an index or part of a name
    int threads = 0;               // extraction threads; 0: all cores
    std::uint64_t slice_bytes = 0; // largest upload to the device; 0: 16 MiB
    std::uint64_t max_memory = 0;  // refuse grids needing more (host and device); 0: no limit
    std::vector<OutputRequest> outputs;
    // A tileset's finest tiles: their edge in x and y, in the CRS's unit, rounded up to whole
    // bricks (4 cells) of the grid; 0: 64 cells. A plan's tiles are a tileset's tiles of its size.
    double tile_size = 0;
    // merge_tiles only: a tileset's sheet meshed tile by tile from the tiles' files (each tile's
    // cells and its neighbours' along its edges), never holding the plan's grid whole; the coarser
    // levels from the tiles' cells coarsened. The same bytes as holding it; on one machine slower
    // (docs/benchmarks.md). Needs a tileset output and the sheet; a grid coarsened after counting
    // its cells (too fine for its points) is meshed whole all the same, said in a note.
    bool mesh_in_tiles = false;
    std::string report;     // also write the RunReport as JSON here (run_report_json); empty: none
    bool keep_mesh = false; // return the mesh in BuildResult (it can be large)
};

// Everything a run measured, in the order of the command line's --report JSON.
struct OutputReport {
    std::string path;
    std::uint64_t bytes = 0;
    double seconds = 0;
};

struct RunReport {
    std::string input, device;               // the input's name ("standard input" for -; "64 files"), the device's
    std::uint64_t input_files = 1;           // the inputs read
    std::vector<std::string> skipped_inputs; // with skip_bad_inputs: each input left out, with its error
    std::uint64_t points_read = 0, points_outside = 0;
    std::vector<std::string> warnings; // "warning: ..." lines to show, e.g. records past the header's count
    GridSpec grid;
    std::string grid_reason; // why this grid, when it was chosen from the data; empty otherwise
    // The input's coordinate system in one line ("NAD83 / Oregon GIC Lambert (ft) (EPSG:2992),
    // projected, in foot (0.3048 m)"), what the outputs record of it ("EPSG:2992", or a WKT),
    // both empty when the input declares none: the mesh is then in the file's own units.
    std::string crs, crs_recorded;
    std::string
        unit; // the CRS's unit of length ("metre", "US survey foot"): of the grid, the bounds; empty without one
    double iso = 0;
    bool iso_auto = false;
    SurfaceKind surface = SurfaceKind::sheet;
    VertexPlacement placement = VertexPlacement::surface;
    std::uint64_t occupied_cells = 0, occupied_bricks = 0, pool_bytes = 0; // the sparse grid
    std::uint64_t median_count = 0;                                        // the median points in an occupied cell
    std::uint64_t host_grid_bytes = 0; // the grid as the host keeps it: occupied cells only
    PieceCount pieces;
    SimplifyReport simplify; // triangles before and after, the bound in file units, seconds
    // Thin parts refined: the cells meshed at half the cell (thin parts and the cells next to
    // them), and the seconds their points' second read took. That read runs while the grid is
    // extracted (its seconds are inside `extract`), or alone before it under max_memory, with one
    // thread and when re-meshing an accumulation (then inside `read_accumulate`).
    std::uint64_t thin_cells = 0;
    double thin_read = 0;
    std::string thin_unrefined; // why no cell was refined ("no thin parts found"); empty with never
    std::size_t vertices = 0, triangles = 0;
    bool colored = false, normals = false;
    Vec3 origin{}; // output positions are relative to it
    std::vector<OutputReport> outputs;
    double read_accumulate = 0, extract = 0, write = 0, total = 0; // seconds (extract includes simplify)
    std::uint64_t peak_rss_bytes = 0;
};

struct BuildResult {
    std::optional<Mesh> mesh; // when options.keep_mesh
    RunReport report;
};

enum class BuildStage { read_accumulate, extract, write };

// Progress callbacks, all no-ops by default: override what you show. Called on the calling
// thread, in order; an exception thrown from one ends the run with that exception.
struct BuildObserver {
    virtual ~BuildObserver() = default;
    // `what` is a short description: "extracting the surface", "writing deck.glb". Called again
    // within a stage as each step of it starts ("simplifying 471971 triangles").
    virtual void stage_started(BuildStage, const std::string& /*what*/) {}
    // `so_far` holds the fields measured up to the end of this stage.
    virtual void stage_ended(BuildStage, const RunReport& /*so_far*/) {}
    // After each slice of records: points so far of the promised total, and the input's bytes
    // consumed (compressed bytes for a compressed stream) of its size when known.
    virtual void points_read(std::uint64_t /*points*/, std::uint64_t /*points_total*/, std::uint64_t /*bytes*/,
                             std::optional<std::uint64_t> /*bytes_total*/) {}
    // One line of detail as a step ends (the command line's --verbose), without a newline.
    virtual void detail(const std::string& /*line*/) {}
};

// Reads `input` (a LAS or LAZ path, or "-" for standard input), sums its points into a grid of cells, extracts the
// surface, removes small pieces, simplifies, computes normals and writes every output (a .glb's
// scene, node, mesh and material are named after the input's file name without extension).
// Throws Error: usage for options that cannot work (no outputs, an output path that is the input
// or another output, an unknown extension, a closed-surface option with the sheet, a grid that
// does not fit), input for an input that gives no mesh (nothing written then), device or output
// otherwise. Every check on the options is made before the input is opened.
BuildResult build_mesh(const std::string& input, const BuildOptions& options, BuildObserver* observer = nullptr);

// The same for a survey delivered as several files, meshed as one cloud: LAS and LAZ, plain or
// compressed, each with its own scale, offset and point format, all in one coordinate system
// (files that declare none are taken to be in it). The grid covers the union of their bounds;
// the mesh does not depend on the order of `inputs`, and is the one build_mesh gives for a single
// file holding all their points when their scales and offsets agree. One file is open at a
// time. A .glb's names are then the output's file name without extension. An input that cannot be
// read stops the run (nothing written) unless options.skip_bad_inputs.
BuildResult build_mesh(const std::vector<std::string>& inputs, const BuildOptions& options,
                       BuildObserver* observer = nullptr);

// Read once, mesh many times (as `lasmesh view` does while its user tries options): the inputs'
// points summed into their grid and kept, with the read's fields of the report.
//
//     lasmesh::BuildOptions options;
//     const lasmesh::AccumulatedInputs read = lasmesh::accumulate_inputs({"deck.las"}, options);
//     options.simplify.error = 0.25;                   // anything but how the inputs are read
//     options.outputs.push_back({"deck.ply"});
//     lasmesh::build_mesh(read, options);              // the bytes `lasmesh deck.las -o deck.ply
//                                                      // --simplify 0.25cell` writes, no re-read
struct Accumulation; // the grid and what the outputs need of the survey (src/build_mesh.cpp)
struct AccumulatedInputs {
    std::vector<std::string> inputs;
    RunReport report; // what the read measured: input, points, grid, CRS, cells; no mesh yet
    std::shared_ptr<const Accumulation> accumulation;
};

// Reads and accumulates as build_mesh does; only the fields that read (grid, bounds, scan_bounds,
// skip_bad_inputs, crs, device, slice_bytes, max_memory) count. Throws Error as build_mesh does.
AccumulatedInputs accumulate_inputs(const std::vector<std::string>& inputs, const BuildOptions& options,
                                    BuildObserver* observer = nullptr);

// Meshes an accumulation and writes the outputs: the same bytes build_mesh(inputs, options)
// writes, without reading the inputs again. The grid is copied (the accumulation stays whole), so
// this needs its host_grid_bytes once more. The accumulation also keeps the last surface
// extracted (before simplification): a call that changes only the simplification, the normals
// or the outputs starts from it, without extracting again. Refining thin parts, the inputs (files)
// are read again for the points near the thin parts, once for each iso: the accumulation keeps
// the last iso's. Calls may come from several threads. Throws Error (usage)
// when `options` read differently from the options the inputs were accumulated with.
BuildResult build_mesh(const AccumulatedInputs& accumulated, const BuildOptions& options,
                       BuildObserver* observer = nullptr);

// The report as one line of JSON (full precision), the fields in the order of the RunReport.
std::string run_report_json(const RunReport& report);

// ---- Over many machines -------------------------------------------------------------------
// A survey too large for one machine's time, read on many: a plan fixes the grid from the
// inputs' headers and cuts it into tiles; each tile job (one task of a Slurm array or a
// Kubernetes Indexed Job) reads only the inputs that touch its tile (of a COPC file, only the
// octree nodes that do) and writes the exact sums of
// its tile's cells; merge adds them into the grid one machine would have accumulated and
// meshes it: every output is byte for byte the one build_mesh writes from the same inputs.
//
//     lasmesh::BuildOptions options;                       // the grid, bounds and CRS to plan with
//     lasmesh::TilePlan plan = lasmesh::plan_tiles(inputs, options, 250.0);   // headers only
//     lasmesh::write_plan(plan, "site.plan.json");
//     // on each node, K from 0 to plan.tiles.size() - 1:
//     lasmesh::run_tile(lasmesh::read_plan("site.plan.json"), K, options);
//     // once every tile is done, with the outputs and meshing options in `options`:
//     options.outputs.push_back({"site/tileset.json"});
//     lasmesh::merge_tiles(lasmesh::read_plan("site.plan.json"), options);
//
// Files: the plan names its tiles' folder, "<plan without .json>-tiles/" beside it, where tile
// K writes "tile-K.cells" (atomically: a rerun replaces it). Inputs and outputs are paths on a
// file system every node sees (a cluster's shared storage).
struct PlannedInput {
    std::string path;         // absolute: tile jobs may start in another folder
    std::uint64_t bytes = 0;  // its size, and its header's point count, when planned: a tile job
    std::uint64_t points = 0; // refuses an input that has changed since
};

// Of a COPC input (a LAZ file whose chunks are the nodes of an octree), the chunks a tile reads:
// those whose node's cube, within the file's header bounds, touches the tile.
struct PlannedChunks {
    std::size_t input = 0;
    std::vector<std::uint64_t> offsets; // each chunk's first byte, ascending
    std::vector<std::uint64_t> points;  // each chunk's point count
};

// A tile: the grid's cells [x_cells[0], x_cells[1]) x [y_cells[0], y_cells[1]), all of z.
struct PlannedTile {
    std::uint32_t x = 0, y = 0; // its place in the tiling
    std::array<std::uint32_t, 2> x_cells{}, y_cells{};
    std::vector<std::size_t> inputs;   // indices into TilePlan::inputs: those whose header bounds touch it
    std::vector<PlannedChunks> chunks; // of those, the COPC inputs read in part (others are read whole)
    std::uint64_t points = 0;          // the points those inputs' headers (or COPC nodes) promise
};

struct TilePlan {
    std::string path;       // the plan's file (read_plan's or write_plan's): the tiles' folder is beside it
    std::uint64_t hash = 0; // of the plan's file: a tile's sums name the plan they belong to
    std::vector<PlannedInput> inputs;
    GridRequest grid_request;       // as asked (automatic: coarsened from the counts when merged)
    std::optional<Bounds> bounds;   // as asked
    std::string crs;                // as asked (empty: the inputs')
    GridSpec grid;                  // the grid every tile accumulates into (automatic: before coarsening)
    std::string unit;               // the CRS's unit of length; empty without a CRS
    double tile_size = 0;           // a tile's edge in x and y, in the CRS's unit (tile_cells cells)
    std::uint32_t tile_cells = 0;   // a multiple of 4 (the grid's bricks)
    std::vector<PlannedTile> tiles; // those that touch an input, by y then x
};

// Reads the inputs' headers only (and COPC files' hierarchies) and fixes the grid and the tiles. `tile_size` in the
// CRS's unit (rounded up to whole bricks of 4 cells); 0: about 20 million promised points a tile. One run
// with BuildOptions::tile_size = plan.tile_size writes the tileset the plan's merge writes. Only the read options
// of `options` count (grid, bounds, crs); scan_bounds and skip_bad_inputs are refused (Error usage): a tile job must
// read exactly the files planned. Throws Error (input) naming an input that cannot be read.
TilePlan plan_tiles(const std::vector<std::string>& inputs, const BuildOptions& options, double tile_size);

// The plan as JSON in `path` (atomically), and read back; read_plan throws Error (input) naming
// what is wrong with the file.
void write_plan(TilePlan& plan, const std::string& path);
TilePlan read_plan(const std::string& path);
// The folder of a plan's tiles, and tile K's file in it.
std::string tiles_folder(const TilePlan& plan);
std::string tile_path(const TilePlan& plan, std::size_t index);

struct TileReport {
    std::size_t index = 0;
    std::string path;                 // the tile's cell sums, written
    std::uint64_t inputs_read = 0;    // the inputs whose headers touch the tile
    std::uint64_t points_read = 0;    // their points
    std::uint64_t points_in_tile = 0; // of those, the points in the tile's cells
    std::uint64_t occupied_cells = 0; // the tile's
    std::uint64_t bytes = 0;          // of its file
    double seconds = 0;
    std::uint64_t peak_rss_bytes = 0;
};

// Reads the inputs of tile `index` and writes its cells' sums. Of `options`, the device, slice
// and memory fields count; slice_bytes 0 is 2 MiB here, not 16 (a tile job holds a small share of
// the grid, so its upload slices are most of its memory above the OpenCL runtime's). Throws Error (usage) for an index
// past the plan's tiles, (input) for an input changed since the plan, or holding a point outside its header's bounds in
// a tile that does not read it (its points would be lost: the message names the file, the record and the tile).
TileReport run_tile(const TilePlan& plan, std::size_t index, const BuildOptions& options,
                    BuildObserver* observer = nullptr);

// Adds the tiles' sums into the grid and meshes it into options.outputs, as build_mesh(inputs,
// options) would with the plan's grid, bounds and CRS (the read fields of `options` are not
// used); a tileset's finest tiles are the plan's tiles (options.tile_size: 0, or the plan's).
// Throws Error (input) listing every tile missing, damaged or from another plan, before reading
// any.
BuildResult merge_tiles(const TilePlan& plan, const BuildOptions& options, BuildObserver* observer = nullptr);

} // namespace lasmesh
