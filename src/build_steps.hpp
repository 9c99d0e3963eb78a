// SPDX-License-Identifier: Apache-2.0
// The steps of build_mesh that a run split over machines (build_mesh.hpp) takes apart: the
// survey's headers opened, the grid reported on, the grid meshed and written. Internal: the
// library's users call build_mesh, or plan, run_tile and merge_tiles.
#pragma once

#include "grid/cell_sums.hpp"
#include "lasmesh/build_mesh.hpp"
#include "mesh/seam.hpp"
#include "mesh/seam_corners.hpp"
#include "mesh/tiled_sheet.hpp"
#include "read/crs.hpp"
#include "read/survey.hpp"

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace lasmesh {

// Thin parts meshed again at half the cell (BuildOptions::refine_thin): the cells of the grid
// whose mesh comes from the finer grid, and that grid, holding the points near them.
struct Refinement {
    std::vector<std::uint64_t> cells; // keys ((z * dims[1] + y) * dims[0] + x) of the grid's cells, ascending
    CellGrid fine;
};

// What reading leaves for meshing: the grid, and what the outputs need of the survey.
struct Accumulation {
    BuildOptions read_options; // the options it was read with (their read fields count)
    CellGrid grid;
    std::optional<CrsInfo> crs;
    std::uint64_t fullest_cell = 0;  // for the message should the mesh come out empty
    std::uint64_t memory_in_use = 0; // before the grid: the program, its libraries, the runtime
    // Inputs the read left out part-way through their records, or the bounds' scan did
    // (skip_bad_inputs), in order: a second read of the inputs leaves them out the same way, so
    // its frame is the grid's.
    std::vector<std::string> left_out;

    // The last surface extracted, small pieces removed, before simplification: a new mesh that
    // changes only the simplification (or the normals, or the outputs) starts from it instead of
    // extracting again. Kept by accumulate_inputs' accumulations only.
    struct Surface {
        double iso = 0;
        SurfaceKind surface{};
        VertexPlacement placement{};
        MinPiece min_piece;
        bool refined = false;         // its thin parts meshed at half the cell (from the iso's)
        std::uint32_t tile_order = 0; // in the order of tiles of this many cells (in_tile_order); 0: the grid's
        std::size_t extracted = 0;    // triangles before small pieces were removed
        PieceCount pieces;
        Mesh mesh;
        bool same_options(double i, const BuildOptions& o, bool thin_refined, std::uint32_t tiles) const {
            return iso == i && surface == o.surface && placement == o.placement &&
                   min_piece.value == o.min_piece.value && min_piece.relative == o.min_piece.relative &&
                   refined == thin_refined && tile_order == tiles;
        }
    };
    bool keeps_surface = false;
    mutable std::mutex surface_mutex; // guards `surface` and `thin_parts`
    mutable std::shared_ptr<const Surface> surface;

    // The thin parts read again for the last iso a refined mesh asked for (they follow from the
    // grid and the iso): another mesh at that iso starts from them without a third read.
    struct ThinParts {
        double iso = 0;
        std::optional<Refinement> refinement;
        std::uint64_t cells = 0; // the report's fields the read set
        double read_seconds = 0;
        std::string unrefined;
    };
    mutable std::shared_ptr<const ThinParts> thin_parts;
};

double seconds_since(std::chrono::steady_clock::time_point start);
// Resident memory now (Linux: /proc/self/statm); 0 where unknown.
std::uint64_t resident_bytes();
// The most memory resident so far.
std::uint64_t peak_rss_bytes();

// The cells along a tile's edge of `size` (in the CRS's unit) in a grid of `cell`: rounded up
// to whole bricks, so a plan's tiles rounded again to a coarser grid's bricks give the tiles that
// `size` gives there (a hair over a whole number of cells, from the product, does not count).
std::uint32_t tile_cells_for(double size, double cell);

// The cells along a tileset's finest tiles' edge, for a tileset of `tile_size` (0: chosen) over
// `finest`: the tiles the finest sheet is ordered by (in_tile_order) and a merge meshes it in.
std::uint32_t finest_tile_cells(const GridSpec& finest, double tile_size);

// The checks on what reading takes: inputs, options that cannot work.
void check_read_options(const std::vector<std::string>& inputs, const BuildOptions& o);
// The checks on what meshing and writing take; returns each output's format.
std::vector<MeshFormat> check_mesh_options(const std::vector<std::string>& inputs, const BuildOptions& o);

// The survey's headers read: the CRS, the frame, the bounds, and how to accumulate them.
struct SurveyStart {
    Survey survey;
    std::unique_ptr<LasReader> single; // one input: open already (standard input too)
    AccumulateOptions accumulate;      // the grid, bounds, slices and memory of `o`
    std::vector<std::string> left_out; // inputs the bounds' scan left out (skip_bad_inputs), in order
};
// Fills the CRS fields and the survey's notes of `r`. Throws Error as build_mesh does.
SurveyStart open_survey(const std::vector<std::string>& inputs, const BuildOptions& o, RunReport& r);

// The detail lines (the observer's) as the read starts.
std::string reading_line(const SurveyReader& reader, bool single_untransformed);
std::string device_line(const ComputeDevice& device);

// The accumulated grid is the finest the mesh uses: one too fine for the points (most occupied
// cells a single point) is coarsened exactly, said in its grid_reason and in a note added to
// `notes`. Not when the iso asked for is below 1 (then a lone point is a surface cell too).
void fit_grid_to_points(CellGrid& grid, const BuildOptions& o, std::vector<std::string>& notes);

// What the report, the automatic iso and the thin parts' check take of a grid's cells: counted
// from them (cell_facts), or by a merge from its tiles' files without holding the cells together.
struct CellFacts {
    std::uint64_t occupied = 0, fullest = 0, median = 0;
    std::uint64_t host_bytes = 0; // CellGrid::host_bytes with the cells held
};
CellFacts cell_facts(const CellGrid& grid);

// The read's fields of `r` from the accumulated grid (r.input and r.device set before; its cells
// as `facts` counts them), and what `a` keeps of the survey; the outputs' placement notes when
// `note_outputs`.
void report_grid(const CellGrid& grid, const CellFacts& facts, const Survey& survey,
                 const std::vector<std::string>& reader_warnings, bool note_outputs, const BuildOptions& o,
                 double seconds, BuildObserver& watch, Accumulation& a, RunReport& r);

// Reads the inputs and sums their points into `a.grid`, then report_grid.
void accumulate_survey(const std::vector<std::string>& inputs, const BuildOptions& o, bool note_outputs,
                       BuildObserver& watch, Accumulation& a, RunReport& r);

// Whether the thin parts of a grid whose occupied cells hold a median of `median` points are
// meshed at half the cell (BuildOptions::refine_thin); when automatic and not, r.thin_unrefined
// says why.
bool refines_thin_parts(const std::vector<std::string>& inputs, const BuildOptions& o, std::uint64_t median,
                        RunReport& r);

// The thin parts' second read, planned from the grid before its extraction releases the cells:
// the cells meshed from the finer grid, the cells whose points are read again, the grid's frame.
struct ThinReadPlan {
    std::vector<std::uint64_t> mesh_cells; // Refinement::cells
    std::vector<std::uint64_t> read_cells; // the same keys: the mesh cells and a cell more around them
    GridSpec spec;                         // the grid's
    std::array<AxisCells, 3> axes;         // the grid's cell starts in the survey's raw integers
};

// Finds the thin parts of `grid` (grid/thin_parts.hpp); nothing, and r.thin_unrefined says why,
// when there are none or half the cell would not fit.
std::optional<ThinReadPlan> plan_thin_read(const BuildOptions& o, const CellGrid& grid, RunReport& r);
// The same from the thin cells found already (thin_cells, or the tiles': survey_tiles).
std::optional<ThinReadPlan> plan_thin_read(const std::vector<std::array<std::int64_t, 3>>& thin_at,
                                           const GridSpec& spec, const std::array<AxisCells, 3>& axes, RunReport& r);

// Reads the inputs again for the points near the thin parts (without those the first read
// `left_out`) into the grid of half the cell. Sets r.thin_cells and r.thin_read.
Refinement read_thin_parts(const ThinReadPlan& plan, const std::vector<std::string>& inputs,
                           const std::vector<std::string>& left_out, const BuildOptions& o, BuildObserver& watch,
                           RunReport& r);

// The mesh of the thin parts at `iso` (the grid's; `iso_auto` when chosen from the grid): the
// finer grid's sheet, with tubes along lines, in the refined cells of `grid` only, ending on
// their faces where the grid's sheet does (`coarse_seam`: its samples at their corners,
// extract_sheet's SeamRequest; may wait for them).
Mesh thin_parts_mesh(const Refinement& refined, double iso, bool iso_auto, const GridSpec& grid,
                     const std::function<const SeamCorners&()>& coarse_seam);

// The finest sheet meshed tile by tile (sheets_of_tiles, with the tiles' survey), and the thin
// parts (`refined`, when given) meshed at half the cell and joined to it where the two meet, as
// mesh_grid joins them to the whole grid's sheet; `seam` says how the join went.
struct TiledFinest {
    Mesh mesh;
    std::optional<SeamReport> seam;
};
TiledFinest finest_sheet_in_tiles(const GridSpec& grid, const std::vector<std::array<std::int64_t, 4>>& windows,
                                  const TilePart& part_of, double iso, bool iso_auto, const SheetSurvey& survey,
                                  const Refinement* refined);

// plan_thin_read, then read_thin_parts.
std::optional<Refinement> refine_thin_parts(const std::vector<std::string>& inputs,
                                            const std::vector<std::string>& left_out, const BuildOptions& o,
                                            const CellGrid& grid, BuildObserver& watch, RunReport& r);

// A grid held by a plan's tiles, never whole (merge_tiles): its finest sheet is meshed tile by
// tile (finest_sheet_in_tiles), its coarser levels come from the tiles' cells coarsened.
struct GridInTiles {
    std::vector<std::array<std::int64_t, 4>> windows; // tile_windows of the tileset's finest tiles
    TilePart part_of;                                 // a window and a halo of 8 cells, from the tiles' files
    double iso = 0;                                   // the grid's: asked for, or from the tiles' counts
    SheetSurvey survey;                               // survey_tiles'
    std::optional<Refinement> refined;                // the thin parts, read already
    CellGrid coarser;                                 // the grid coarsened once (coarsen_grid), from the tiles
};

// Extracts the mesh of `grid` (the accumulation's, or a copy of it) and writes every output;
// `r` holds the read's fields, `seconds_before` the time the read took. The thin parts come
// read already (`refined`), or are read while the grid is extracted (`thin_read`, from the
// inputs but those `a` left out; first, under a memory limit or with one thread), or not at all.
// With `in_tiles`, `grid` is the grid's frame only (its spec, axes and bricks, not its cells): a
// tileset's sheet meshed from the tiles, as the whole grid's, ordered by its tiles, is.
BuildResult mesh_grid(CellGrid&& grid, const Accumulation& a, RunReport r, const std::vector<std::string>& inputs,
                      const BuildOptions& o, const std::vector<MeshFormat>& formats, BuildObserver& watch,
                      double seconds_before, const Refinement* refined = nullptr,
                      const ThinReadPlan* thin_read = nullptr, GridInTiles* in_tiles = nullptr);

// A window of the plan's grid (x from window[0] to window[1], y from window[2] to window[3], in
// its cells) and `halo` cells round it, read from the files of the tiles that hold them: the
// bricks bricks_within would cut from the whole grid, with the geometry of `frame` (its spec,
// axes, raw frame, colour and moments; not its cells). Throws Error (input) naming a tile's file
// that is missing, damaged or another plan's.
CellGrid planned_part(const TilePlan& plan, const std::array<std::int64_t, 4>& window, std::int64_t halo,
                      const CellGrid& frame);

// For a plan's tile jobs and its merge (src/tile_plan.cpp): the plan's inputs; `options` with
// the plan's read fields (grid, bounds, CRS); and open_survey of the inputs as planned, refusing
// (Error input) an input whose size or point count changed since.
std::vector<std::string> planned_paths(const TilePlan& plan);
BuildOptions planned_options(const TilePlan& plan, BuildOptions options);
SurveyStart open_planned_survey(const TilePlan& plan, const BuildOptions& planned, RunReport& r);

} // namespace lasmesh
