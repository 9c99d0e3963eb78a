// SPDX-License-Identifier: Apache-2.0
// run_tile: one tile of a plan. The survey's headers are read as one machine reads them (the
// same CRS, frame and layout, so the same raw integers and cells), then only the inputs planned
// for the tile are read, and only their points inside the tile go on to the device, into the
// tile's window of the plan's grid; of a COPC file, only the chunks (octree nodes) the plan lists for the tile are
// read. Each point read is checked on the host: one in the grid but in a tile that does not read it lies outside its
// file's header bounds (or its node's cube), and would be lost: the job stops, naming it.
#include "lasmesh/build_mesh.hpp"

#include "build_steps.hpp"
#include "byte_order.hpp"
#include "grid/axis_cells.hpp"
#include "grid/memory_guard.hpp"
#include "grid/tile_cells.hpp"
#include "lasmesh/error.hpp"
#include "number_text.hpp"
#include "read/decode_ahead.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <numeric>

namespace lasmesh {

namespace {

// A tile job's default upload slice: on the 181M deck in 8 tiles, 114-130 MB a job against
// 142-158 MB with the main job's 16 MiB, in no more time (docs/benchmarks.md).
constexpr std::uint64_t tile_slice_bytes = std::uint64_t{2} << 20;

// Where a raw position lies: outside the grid, or in a column and row of the tiling.
struct TileLocator {
    std::array<AxisCells, 3> axes;
    std::array<std::vector<std::int64_t>, 2> tile_starts; // per x, y: each tile column's first raw value, then the end

    TileLocator(const TilePlan& plan, const LasHeader& header) {
        for (int a = 0; a < 3; ++a) axes[a] = axis_cells(plan.grid, a, header.scale[a], header.offset[a]);
        for (int a = 0; a < 2; ++a) {
            const std::vector<std::int64_t>& starts = axes[a].starts;
            for (std::size_t i = 0; i + 1 < starts.size(); i += plan.tile_cells) tile_starts[a].push_back(starts[i]);
            tile_starts[a].push_back(starts.back());
        }
    }
    bool inside(const std::array<std::int64_t, 3>& raw) const {
        for (int a = 0; a < 3; ++a)
            if (raw[a] < axes[a].starts.front() || raw[a] >= axes[a].starts.back()) return false;
        return true;
    }
    // The tile column (a = 0) or row (a = 1) of a raw value inside the grid.
    std::uint32_t tile_of(int a, std::int64_t raw) const {
        const std::vector<std::int64_t>& s = tile_starts[a];
        return static_cast<std::uint32_t>(std::upper_bound(s.begin() + 1, s.end() - 1, raw) - (s.begin() + 1));
    }
};

// Raw integers [lo, hi) as a start and a width: v lies there when v - start, unsigned, is below
// the width, one comparison (an empty range has width 0).
struct RawRange {
    std::int64_t start;
    std::uint64_t width;
    RawRange(std::int64_t lo, std::int64_t hi)
        : start(lo), width(static_cast<std::uint64_t>(std::max(hi - lo, std::int64_t{0}))) {}
    bool holds(std::int64_t v) const { return static_cast<std::uint64_t>(v - start) < width; }
};

// The tiles that read one chunk of an input (the whole file, unless it is a COPC file read in part).
struct ChunkReaders {
    std::uint64_t points = 0;         // in the chunk, as planned
    std::uint64_t offset = 0;         // its first byte (a COPC chunk)
    std::vector<std::uint32_t> tiles; // y * columns + x of each tile that reads it, ascending
    // Where those tiles form a rectangle (as they do for a file or a COPC node read by the tiles
    // its bounds touch), the raw x and y they span, [x0, x1) and [y0, y1): a point there is in
    // a tile that reads it, told by four comparisons; otherwise empty.
    std::array<std::int64_t, 4> span{};
    bool owns_outside = false; // this tile is the first to read it: it counts its points outside the grid
    bool copc = false;
};

// For tile `index` reading `input`: its chunks in the order it reads them, and who else reads each.
std::vector<ChunkReaders> chunk_readers(const TilePlan& plan, std::size_t index, std::size_t input,
                                        const TileLocator& locate) {
    const std::uint32_t columns = static_cast<std::uint32_t>(locate.tile_starts[0].size() - 1);
    const auto planned = [&](const PlannedTile& t) -> const PlannedChunks* {
        for (const PlannedChunks& c : t.chunks)
            if (c.input == input) return &c;
        return nullptr;
    };
    std::vector<ChunkReaders> chunks;
    std::vector<std::uint64_t> offsets; // of this tile's chunks
    if (const PlannedChunks* mine = planned(plan.tiles[index])) {
        offsets = mine->offsets;
        for (std::size_t c = 0; c < offsets.size(); ++c)
            chunks.push_back({mine->points[c], offsets[c], {}, false, true});
    } else {
        chunks.push_back({~std::uint64_t{0}, 0, {}, false, false});
    }
    for (std::size_t k = 0; k < plan.tiles.size(); ++k) {
        const PlannedTile& t = plan.tiles[k];
        if (!std::binary_search(t.inputs.begin(), t.inputs.end(), input)) continue;
        const PlannedChunks* theirs = planned(t);
        for (std::size_t c = 0; c < chunks.size(); ++c) {
            // A tile that reads the file whole reads every chunk.
            if (theirs && !std::binary_search(theirs->offsets.begin(), theirs->offsets.end(), offsets[c])) continue;
            if (chunks[c].tiles.empty()) chunks[c].owns_outside = k == index;
            chunks[c].tiles.push_back(t.y * columns + t.x);
        }
    }
    for (ChunkReaders& c : chunks) {
        std::sort(c.tiles.begin(), c.tiles.end());
        std::array<std::uint32_t, 4> in_tiles{UINT32_MAX, 0, UINT32_MAX, 0}; // x0, x1, y0, y1, inclusive
        for (const std::uint32_t t : c.tiles) {
            in_tiles[0] = std::min(in_tiles[0], t % columns), in_tiles[1] = std::max(in_tiles[1], t % columns);
            in_tiles[2] = std::min(in_tiles[2], t / columns), in_tiles[3] = std::max(in_tiles[3], t / columns);
        }
        if (!c.tiles.empty() &&
            c.tiles.size() == std::size_t{in_tiles[1] - in_tiles[0] + 1} * (in_tiles[3] - in_tiles[2] + 1))
            c.span = {locate.tile_starts[0][in_tiles[0]], locate.tile_starts[0][in_tiles[1] + 1],
                      locate.tile_starts[1][in_tiles[2]], locate.tile_starts[1][in_tiles[3] + 1]};
    }
    return chunks;
}

} // namespace

TileReport run_tile(const TilePlan& plan, std::size_t index, const BuildOptions& o, BuildObserver* observer) {
    const auto start = std::chrono::steady_clock::now();
    BuildObserver silent;
    BuildObserver& watch = observer ? *observer : silent;
    if (index >= plan.tiles.size())
        throw Error(ErrorKind::usage,
                    "tile " + std::to_string(index) + " is not in " + plan.path + ": its tiles are 0 to " +
                        std::to_string(plan.tiles.size() - 1),
                    "index");
    std::optional<tbb::global_control> thread_limit;
    if (o.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, o.threads);
    const PlannedTile& tile = plan.tiles[index];

    // The whole survey's headers, as one machine reads them.
    RunReport r;
    SurveyStart opened = open_planned_survey(plan, planned_options(plan, o), r);
    const Survey& survey = opened.survey;

    // Only the tile's inputs (of a COPC input, only its planned chunks), in the survey's frame and layout.
    Survey part = survey;
    part.files.clear();
    part.header.point_count = 0;
    for (const std::size_t i : tile.inputs) {
        part.files.push_back(survey.files[i]);
        std::uint64_t points = survey.files[i].point_count;
        for (const PlannedChunks& c : tile.chunks)
            if (c.input == i) {
                points = std::accumulate(c.points.begin(), c.points.end(), std::uint64_t{0});
                part.files.back().chunks = c.offsets, part.files.back().chunk_points = points;
            }
        part.header.point_count += points;
    }
    LasReader* single = plan.inputs.size() == 1 ? opened.single.get() : nullptr;
    if (single && !part.files.front().chunks.empty()) read_only_chunks(*single, part.files.front());

    const TileLocator locate(plan, survey.header);
    const std::uint32_t columns = static_cast<std::uint32_t>(locate.tile_starts[0].size() - 1);
    std::vector<ChunkReaders> readers; // of the file being read, its chunks in the order read
    std::size_t readers_for = ~std::size_t{0}, chunk = 0;
    std::uint64_t left_in_chunk = 0, points_read = 0;
    std::vector<TileInputCount> counts(tile.inputs.size());
    for (std::size_t i = 0; i < tile.inputs.size(); ++i) counts[i].input = tile.inputs[i];
    const std::size_t length = survey.header.point_record_length;
    // Each point is counted by one tile: the tile it lies in, or, outside the grid, the first tile
    // that reads it. This one keeps the records in its tile (moved to the front), counts those it
    // owns outside the grid, passes over those of another tile that reads them, and stops at any
    // other (a point no tile would keep). Most points lie in this tile or in the span of the
    // others that read the chunk, told by comparisons without branches (a branch on where each
    // point lies is mispredicted as often as the tiles share the input); only the rest are looked
    // at one by one.
    const std::int64_t x0 = locate.axes[0].starts[tile.x_cells[0]], x1 = locate.axes[0].starts[tile.x_cells[1]];
    const std::int64_t y0 = locate.axes[1].starts[tile.y_cells[0]], y1 = locate.axes[1].starts[tile.y_cells[1]];
    const std::int64_t z0 = locate.axes[2].starts.front(), z1 = locate.axes[2].starts.back();
    std::vector<std::uint32_t> in_tile; // of the records handed over, those in this tile
    const auto keep = [&](std::size_t file, std::byte* records, std::size_t count) {
        const std::size_t input = tile.inputs[file];
        if (readers_for != input) {
            readers = chunk_readers(plan, index, input, locate);
            readers_for = input, chunk = 0, left_in_chunk = readers.front().points;
        }
        points_read += count;
        TileInputCount& c = counts[file];
        in_tile.resize(count);
        std::size_t kept = 0;
        for (std::size_t first = 0; first < count;) {
            while (left_in_chunk == 0 && chunk + 1 < readers.size()) left_in_chunk = readers[++chunk].points;
            const ChunkReaders& r = readers[chunk];
            // The records of this call in the current chunk (past its planned points, the last chunk's).
            const std::size_t end =
                left_in_chunk == 0
                    ? count
                    : first + static_cast<std::size_t>(std::min<std::uint64_t>(left_in_chunk, count - first));
            // Made here so that they stay in registers (the counts written below might alias them).
            const RawRange tile_x(x0, x1), tile_y(y0, y1), grid_z(z0, z1);
            const RawRange span_x(r.span[0], r.span[1]), span_y(r.span[2], r.span[3]);
            const std::size_t size = length;
            std::uint32_t* order = in_tile.data();
            for (std::size_t i = first; i < end; ++i) {
                const std::byte* at = records + i * size;
                const std::array<std::int64_t, 3> raw{load_le<std::int32_t>(at), load_le<std::int32_t>(at + 4),
                                                      load_le<std::int32_t>(at + 8)};
                const bool in_z = grid_z.holds(raw[2]);
                const bool ours = in_z & tile_x.holds(raw[0]) & tile_y.holds(raw[1]);
                const bool theirs = in_z & span_x.holds(raw[0]) & span_y.holds(raw[1]);
                order[kept] = static_cast<std::uint32_t>(i);
                kept += ours;
                if (ours | theirs) continue;
                if (!in_z || !locate.inside(raw)) {
                    if (r.owns_outside) ++c.records, ++c.outside;
                    continue;
                }
                const std::uint32_t tx = locate.tile_of(0, raw[0]), ty = locate.tile_of(1, raw[1]);
                if (std::binary_search(r.tiles.begin(), r.tiles.end(), ty * columns + tx)) continue;
                const SurveyFile& f = survey.files[input];
                const LasHeader& h = survey.header;
                const std::uint64_t record = r.points - left_in_chunk + (i - first); // in the file, or in its chunk
                const std::string where = "x " + shortest(double(raw[0]) * h.scale[0] + h.offset[0]) + ", y " +
                                          shortest(double(raw[1]) * h.scale[1] + h.offset[1]) +
                                          ", outside the file's header bounds (x " + shortest(f.min[0]) + " to " +
                                          shortest(f.max[0]) + ", y " + shortest(f.min[1]) + " to " +
                                          shortest(f.max[1]) + ")" + (r.copc ? " or its COPC node's cube" : "");
                throw_input_error(
                    f.path,
                    "point record " + std::to_string(record) +
                        (r.copc ? " of its COPC chunk at byte " + std::to_string(r.offset) : std::string()) +
                        " lies at " + where +
                        ", in a tile that does not read it, so its points would be lost: correct the "
                        "header's bounds (a scan of its points gives the true ones) and plan again, or "
                        "mesh on one machine reading the points for their bounds",
                    "scan_bounds");
            }
            left_in_chunk -= end - first; // wraps, as one record at a time would, past the last chunk's points
            first = end;
        }
        c.records += kept;
        // The tile's records to the front, in their order (each moves down, never over one still to move).
        for (std::size_t k = 0; k < kept; ++k)
            if (in_tile[k] != k) std::memcpy(records + k * length, records + std::size_t{in_tile[k]} * length, length);
        return kept;
    };

    ComputeDevice device(o.device);
    AccumulateOptions accumulate = opened.accumulate;
    // The device accumulates the tile's window of the plan's grid (all of z): its brick index
    // follows the tile, not the survey (a survey 4,096 cells square and 256 high has a 268 MB
    // index). The window's cells start on the plan's raw integers, and its bricks are the
    // grid's bricks, renumbered below.
    const std::array<std::uint32_t, 3> first{tile.x_cells[0], tile.y_cells[0], 0};
    GridSpec window = plan.grid;
    window.dims = {tile.x_cells[1] - tile.x_cells[0], tile.y_cells[1] - tile.y_cells[0], plan.grid.dims[2]};
    std::array<AxisCells, 3> window_axes;
    for (int a = 0; a < 3; ++a) {
        window.origin[a] = plan.grid.origin[a] + first[a] * plan.grid.cell_size; // for the record only
        const std::vector<std::int64_t>& starts = locate.axes[a].starts;
        window_axes[a].starts.assign(starts.begin() + first[a], starts.begin() + first[a] + window.dims[a] + 1);
    }
    accumulate.spec = window, accumulate.axes = window_axes;
    if (o.slice_bytes == 0) accumulate.slice_bytes = tile_slice_bytes;
    accumulate.memory_in_use = resident_bytes();
    SurveyReader reader(part, single);
    reader.on_records(keep);
    watch.stage_started(BuildStage::read_accumulate,
                        "reading " + std::to_string(part.files.size()) + " inputs of tile " + std::to_string(index));
    watch.detail(reading_line(reader, false));
    watch.detail(device_line(device));
    accumulate.on_slice = [&](std::uint64_t points) {
        watch.points_read(points, part.header.point_count, reader.bytes_read(), reader.bytes_total());
    };
    CellGrid grid;
    try {
        grid = accumulate_cells(reader, device, accumulate);
    } catch (const Error& e) {
        if (e.option() != "grid") throw;
        // Said of the window, a grid that would fit is no advice for a tile job (it has no grid
        // to ask for): the plan's cells or tiles, or the job's memory, are what can change.
        std::string why = e.what();
        for (const char* tail : {"; a grid of ", " (nothing was written)"})
            if (const std::size_t at = why.find(tail); at != std::string::npos) why.resize(at);
        throw Error(ErrorKind::usage,
                    "tile " + std::to_string(index) + " of " + plan.path + " (" + dims_text(window) +
                        " cells of the plan's " + dims_text(plan.grid) + "): " + why +
                        "; plan again with larger cells or smaller tiles, or let the job use more memory "
                        "(nothing was written)",
                    "max_memory");
    }
    // The window's bricks as the plan's grid numbers them: the same order (z, then y, then x).
    const std::array<std::uint32_t, 3> bricks = brick_dims(plan.grid), window_bricks = grid.bricks;
    for (std::uint64_t& key : grid.brick_keys) {
        const std::uint64_t x = key % window_bricks[0], y = key / window_bricks[0] % window_bricks[1],
                            z = key / window_bricks[0] / window_bricks[1];
        key = (z * bricks[1] + y + first[1] / CellGrid::brick_size) * bricks[0] + x + first[0] / CellGrid::brick_size;
    }
    grid.spec = plan.grid, grid.bricks = bricks, grid.axes = locate.axes;
    grid.index_bricks();

    // Only the tile's points reached the device: its bricks are the grid's (a tile's cells start
    // and end on bricks), written in key order, each brick's cells after the last's.
    TileCells written; // what the file says besides the grid's cells
    written.plan_hash = plan.hash;
    written.index = index;
    written.color = grid.color;
    written.color_max_word = grid.color_max_word;
    written.device = device.info().name;
    written.inputs = counts;
    for (std::size_t w = 0; w < reader.warnings().size(); ++w)
        written.warnings.push_back({tile.inputs[reader.warning_files()[w]], reader.warnings()[w]});
    TileReport report;
    for (const CellSums& c : grid.cells) report.points_in_tile += c.count;
    std::error_code failed;
    std::filesystem::create_directories(tiles_folder(plan), failed);
    if (failed)
        throw Error(ErrorKind::output, tiles_folder(plan) + ": cannot create the tiles' folder: " + failed.message());
    report.index = index;
    report.path = tile_path(plan, index);
    report.bytes = write_tile_cells(written, report.path, &grid); // the grid's cells, without a copy
    report.inputs_read = tile.inputs.size();
    report.points_read = points_read;
    report.occupied_cells = grid.cells.size();
    report.seconds = seconds_since(start);
    report.peak_rss_bytes = peak_rss_bytes();
    return report;
}

} // namespace lasmesh
