// SPDX-License-Identifier: Apache-2.0
// merge_tiles: every tile's file checked and every input's points accounted for, then the plan's
// grid meshed as build_mesh meshes the grid it accumulates itself: the same outputs, byte for
// byte. The tiles' cells are added into the grid (the tiles partition its cells) and it is meshed
// whole; or, asked to (mesh_in_tiles), a tileset's sheet is meshed tile by tile from the tiles'
// files (GridInTiles) and the coarser levels come from the tiles' cells coarsened, so the grid's
// cells are never held together.
#include "lasmesh/build_mesh.hpp"

#include "build_steps.hpp"
#include "grid/auto_grid.hpp"
#include "grid/axis_cells.hpp"
#include "grid/tile_cells.hpp"
#include "lasmesh/error.hpp"
#include "mesh/marching_cubes.hpp"
#include "read/input_stream.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <map>

namespace lasmesh {

namespace {

// The cells' counts of points, tallied tile by tile: their median as CellGrid::median_count
// finds it, without the cells held together.
struct CountTally {
    std::vector<std::uint64_t> small = std::vector<std::uint64_t>(1024); // cells of each count below 1024
    std::map<std::uint64_t, std::uint64_t> large;                        // cells of each count above
    std::uint64_t cells = 0, fullest = 0;
    void add(std::uint64_t count) {
        if (count < small.size())
            ++small[count];
        else
            ++large[count];
        ++cells, fullest = std::max(fullest, count);
    }
    // The count at place cells / 2 in ascending order (0 for no cells).
    std::uint64_t median() const {
        std::uint64_t seen = 0;
        for (std::uint64_t n = 0; n < small.size(); ++n)
            if ((seen += small[n]) > cells / 2) return n;
        for (const auto& [n, how_many] : large)
            if ((seen += how_many) > cells / 2) return n;
        return 0;
    }
};

// Tile numbers as a Slurm array spells them: 2,5,9-12.
std::string index_list(const std::vector<std::size_t>& indices) {
    std::string text;
    for (std::size_t i = 0; i < indices.size();) {
        std::size_t j = i;
        while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1) ++j;
        text += (text.empty() ? "" : ",") + std::to_string(indices[i]) +
                (j > i ? "-" + std::to_string(indices[j]) : std::string());
        i = j + 1;
    }
    return text;
}

} // namespace

BuildResult merge_tiles(const TilePlan& plan, const BuildOptions& options, BuildObserver* observer) {
    const auto start = std::chrono::steady_clock::now();
    BuildObserver silent;
    BuildObserver& watch = observer ? *observer : silent;
    const std::vector<std::string> paths = planned_paths(plan);
    if (options.tile_size != 0 && options.tile_size != plan.tile_size)
        throw Error(ErrorKind::usage, "the plan fixes the tiles' size: leave it out of the merge", "tile");
    BuildOptions o = planned_options(plan, options);
    o.tile_size = plan.tile_size; // a tileset's finest tiles are the plan's
    if (o.refine_thin == ThinRefinement::always) check_read_options(paths, o); // the inputs are read again
    const std::vector<MeshFormat> formats = check_mesh_options(paths, o);
    if (o.mesh_in_tiles && (o.surface != SurfaceKind::sheet ||
                            std::find(formats.begin(), formats.end(), MeshFormat::tileset) == formats.end()))
        throw Error(ErrorKind::usage,
                    "meshing in tiles makes a tileset's sheet: give a tileset output (-o DIR/tileset.json) and "
                    "leave the surface a sheet",
                    "in_tiles");
    std::optional<tbb::global_control> thread_limit;
    if (o.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, o.threads);

    // Every tile first: all that are missing or damaged are named together, before any meshing.
    // Only their bricks are kept from this read: their cells are read again one tile at a time
    // into the grid, so the merge holds the grid and one tile's cells, not all tiles' twice.
    watch.stage_started(BuildStage::read_accumulate, "reading " + std::to_string(plan.tiles.size()) + " tiles");
    std::vector<TileCells> tiles(plan.tiles.size());
    CountTally counts;
    std::vector<std::size_t> bad;
    std::string reasons;
    for (std::size_t k = 0; k < plan.tiles.size(); ++k) {
        std::string problem;
        try {
            tiles[k] = read_tile_cells(tile_path(plan, k));
            if (tiles[k].plan_hash != plan.hash || tiles[k].index != k)
                problem = tile_path(plan, k) + ": from another plan, or another tile (written before the plan "
                                               "changed?)";
        } catch (const Error& e) {
            problem = e.what();
        }
        if (!problem.empty()) {
            bad.push_back(k);
            if (bad.size() <= 5) reasons += "\n  " + problem;
            tiles[k] = TileCells{};
        }
        for (const CellSums& cell : tiles[k].cells) counts.add(cell.count);
        std::vector<CellSums>().swap(tiles[k].cells);
    }
    if (!bad.empty()) // the suggestion: the tiles to run again, as an array job's indices
        throw Error(ErrorKind::input,
                    std::to_string(bad.size()) + " of " + std::to_string(plan.tiles.size()) +
                        " tiles missing or damaged: " + index_list(bad) + reasons + (bad.size() > 5 ? "\n  ..." : "") +
                        "\nrun those tiles again, then merge",
                    "tiles", index_list(bad));

    // The survey's headers, as one machine reads them: the frame, the CRS, the notes.
    RunReport r;
    SurveyStart opened = open_planned_survey(plan, o, r);
    const Survey& survey = opened.survey;
    const LasHeader& header = survey.header;

    CellGrid grid;
    grid.spec = plan.grid;
    for (int a = 0; a < 3; ++a) {
        grid.axes[a] = axis_cells(plan.grid, a, header.scale[a], header.offset[a]);
        grid.bricks[a] =
            static_cast<std::uint32_t>((plan.grid.dims[a] + CellGrid::brick_size - 1) / CellGrid::brick_size);
    }
    grid.scale = header.scale, grid.offset = header.offset;
    grid.moments = true; // every tile's file holds its cells' moments
    // Bricks in ascending key order from every tile (the tiles hold disjoint bricks).
    std::vector<std::tuple<std::uint64_t, std::uint32_t, std::uint32_t>> order; // key, tile, brick
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        for (std::size_t b = 0; b < tiles[k].brick_keys.size(); ++b)
            order.emplace_back(tiles[k].brick_keys[b], static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(b));
        grid.color = grid.color || tiles[k].color;
        grid.color_max_word = std::max(grid.color_max_word, tiles[k].color_max_word);
    }
    std::sort(order.begin(), order.end());
    std::vector<std::vector<std::uint32_t>> placed(tiles.size()); // per tile and brick: its place in the grid
    for (std::size_t k = 0; k < tiles.size(); ++k) placed[k].resize(tiles[k].brick_keys.size());
    std::uint64_t cell_count = 0;
    for (std::size_t i = 0; i < order.size(); ++i) {
        const auto [key, k, b] = order[i];
        if (i > 0 && std::get<0>(order[i - 1]) == key)
            throw_input_error(tile_path(plan, k), "holds a brick tile " + std::to_string(std::get<1>(order[i - 1])) +
                                                      " holds too: the tiles do not belong to one plan");
        placed[k][b] = static_cast<std::uint32_t>(i);
        grid.brick_keys.push_back(key);
        grid.brick_masks.push_back(tiles[k].brick_masks[b]);
        grid.brick_first.push_back(cell_count);
        cell_count += static_cast<std::uint64_t>(std::popcount(tiles[k].brick_masks[b]));
    }
    // Meshed from the tiles unless one run would coarsen the grid after counting its cells
    // (fit_grid_to_points, finish_chosen_grid): those coarsen it whole.
    r.input = paths.size() == 1 ? opened.single->stream().name() : std::to_string(paths.size()) + " files";
    std::optional<GridChoice> choice;
    if (plan.grid_request.kind == GridRequest::Kind::automatic)
        choice = choose_grid(header.point_count, plan.bounds.value_or(Bounds{header.min, header.max}), r.input);
    const std::uint64_t median = counts.median();
    const bool coarsened =
        std::max({grid.spec.dims[0], grid.spec.dims[1], grid.spec.dims[2]}) > auto_grid_min_cells &&
        ((choice && median > 0 && median < choice->min_median) || (!(o.iso && *o.iso < 1) && median == 1));
    const bool in_tiles = o.mesh_in_tiles && !coarsened;
    if (o.mesh_in_tiles && coarsened)
        r.warnings.push_back("note: the grid is coarsened after counting its cells (too fine for its points): "
                             "meshed whole, not in tiles");
    std::vector<CellGrid> coarse_parts; // in tiles: each tile's cells coarsened
    if (!in_tiles) grid.cells.resize(cell_count);
    std::uint64_t in_cells = 0;
    const auto same_counts = [](const TileInputCount& a, const TileInputCount& b) {
        return a.input == b.input && a.records == b.records && a.outside == b.outside;
    };
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        const TileCells again = read_tile_cells(tile_path(plan, k));
        if (again.plan_hash != tiles[k].plan_hash || again.brick_keys != tiles[k].brick_keys ||
            again.brick_masks != tiles[k].brick_masks ||
            !std::equal(again.inputs.begin(), again.inputs.end(), tiles[k].inputs.begin(), tiles[k].inputs.end(),
                        same_counts))
            throw_input_error(tile_path(plan, k), "changed while the merge read it: run the merge again");
        CellGrid part = empty_like(grid);
        for (std::size_t b = 0; b < again.brick_keys.size(); ++b) {
            const auto n = static_cast<std::uint64_t>(std::popcount(again.brick_masks[b]));
            const CellSums* from = again.cells.data() + again.brick_first[b];
            if (in_tiles)
                append_brick(part, again.brick_keys[b], again.brick_masks[b], from);
            else
                std::copy_n(from, n, grid.cells.data() + grid.brick_first[placed[k][b]]);
            for (std::uint64_t c = 0; c < n; ++c) in_cells += from[c].count;
        }
        if (in_tiles) {
            part.index_bricks();
            coarse_parts.push_back(coarsen_grid(part));
        }
    }
    grid.index_bricks();

    // Every input's points: each counted by one tile (the one it lies in, or outside the grid the
    // first to read it), so the counts add up to the input's.
    std::vector<std::optional<TileInputCount>> per_input(plan.inputs.size());
    std::map<std::uint64_t, std::vector<std::string>> warnings; // per input, from the first tile to read it
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        for (const TileInputCount& c : tiles[k].inputs) {
            if (c.input >= per_input.size())
                throw_input_error(tile_path(plan, k), "names input " + std::to_string(c.input) + ", not in the plan");
            std::optional<TileInputCount>& seen = per_input[c.input];
            if (!seen) {
                seen = TileInputCount{c.input, 0, 0};
                for (const TileWarning& w : tiles[k].warnings)
                    if (w.input == c.input) warnings[c.input].push_back(w.text);
            }
            seen->records += c.records, seen->outside += c.outside;
        }
    }
    for (std::size_t i = 0; i < per_input.size(); ++i) {
        if (survey.files[i].point_count == 0) continue;
        if (!per_input[i]) throw_input_error(plan.inputs[i].path, "no tile read it: the plan is damaged");
        if (per_input[i]->records != plan.inputs[i].points)
            throw_input_error(plan.inputs[i].path,
                              "the tiles counted " + std::to_string(per_input[i]->records) + " of its " +
                                  std::to_string(plan.inputs[i].points) +
                                  " points: did it change while the tiles ran? Rerun every tile that reads it");
        grid.points_read += per_input[i]->records;
        grid.points_outside += per_input[i]->outside;
    }
    if (in_cells + grid.points_outside != grid.points_read)
        throw Error(ErrorKind::input, "the tiles' cells hold " + std::to_string(in_cells) + " points and " +
                                          std::to_string(grid.points_outside) +
                                          " lie outside the grid, but the inputs "
                                          "hold " +
                                          std::to_string(grid.points_read) + ": the tiles do not belong to one plan");
    std::vector<std::string> reader_warnings;
    for (auto& [input, texts] : warnings) reader_warnings.insert(reader_warnings.end(), texts.begin(), texts.end());

    r.device = tiles.front().device;
    Accumulation a;
    a.memory_in_use = resident_bytes();
    const double seconds = seconds_since(start);
    // Thin parts are found over the whole grid (a tile's with a halo), so the merge reads the
    // points near them itself, from every input, as one machine reads them a second time.
    if (!in_tiles) {
        if (choice) finish_chosen_grid(grid, *choice); // as accumulate_cells chooses it
        fit_grid_to_points(grid, o, reader_warnings);
        report_grid(grid, cell_facts(grid), survey, reader_warnings, true, o, seconds, watch, a, r);
        std::optional<ThinReadPlan> thin_read;
        if (refines_thin_parts(paths, o, grid.median_count(), r)) thin_read = plan_thin_read(o, grid, r);
        return mesh_grid(std::move(grid), a, std::move(r), paths, o, formats, watch, seconds_since(start), nullptr,
                         thin_read ? &*thin_read : nullptr);
    }
    if (choice) grid.grid_reason = "auto: " + choice->reason; // finish_chosen_grid, coarsening nothing
    const CellFacts facts{counts.cells, counts.fullest, median, grid.host_bytes() + counts.cells * sizeof(CellSums)};
    report_grid(grid, facts, survey, reader_warnings, true, o, seconds, watch, a, r);
    const CellGrid frame = empty_like(grid); // the parts' geometry, past the move of `grid`
    GridInTiles tiled;
    tiled.iso = o.iso ? *o.iso : automatic_iso(median);
    tiled.windows = tile_windows(grid.spec, finest_tile_cells(grid.spec, o.tile_size));
    tiled.part_of = [&](const std::array<std::int64_t, 4>& w) { return planned_part(plan, w, 8, frame); };
    watch.stage_started(BuildStage::extract, "surveying " + std::to_string(tiled.windows.size()) + " tiles");
    const bool thin = refines_thin_parts(paths, o, median, r);
    TiledSurvey first = survey_tiles(grid.spec, tiled.windows, tiled.part_of, tiled.iso, thin);
    tiled.survey = std::move(first.survey);
    if (thin)
        if (const std::optional<ThinReadPlan> thin_read = plan_thin_read(first.thin, grid.spec, grid.axes, r)) {
            tiled.refined = read_thin_parts(*thin_read, paths, {}, o, watch, r);
            r.read_accumulate += r.thin_read;
        }
    tiled.coarser = sum_of_parts(std::move(coarse_parts));
    tiled.coarser.points_read = grid.points_read, tiled.coarser.points_outside = grid.points_outside;
    return mesh_grid(std::move(grid), a, std::move(r), paths, o, formats, watch, seconds_since(start), nullptr, nullptr,
                     &tiled);
}

} // namespace lasmesh
