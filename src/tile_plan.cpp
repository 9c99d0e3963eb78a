// SPDX-License-Identifier: Apache-2.0
// plan_tiles and the plan's file: the grid fixed from the headers, cut into square tiles of whole
// bricks in x and y, each listing the inputs whose header bounds (in the survey's CRS) touch it,
// and of a COPC input the octree nodes whose cubes do.
#include "lasmesh/build_mesh.hpp"

#include "build_steps.hpp"
#include "grid/auto_grid.hpp"
#include "io/json.hpp"
#include "io/output_file.hpp"
#include "lasmesh/error.hpp"
#include "read/copc.hpp"
#include "read/input_stream.hpp"
#include "read/las_header.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace lasmesh {

namespace {

// About this many promised points a tile when no tile size is given: a tile job's memory is
// then that of meshing 20 million points (a few hundred MB), and the survey has enough tiles to
// keep a few dozen nodes busy from a billion points on.
constexpr double default_points_per_tile = 20e6;

std::uint64_t fnv1a(const std::string& bytes) {
    std::uint64_t hash = 0xcbf29ce484222325ULL;
    for (const char c : bytes) hash = (hash ^ static_cast<unsigned char>(c)) * 0x100000001b3ULL;
    return hash;
}

const char* request_kind(GridRequest::Kind kind) {
    switch (kind) {
    case GridRequest::Kind::automatic: return "automatic";
    case GridRequest::Kind::longest_axis: return "longest";
    case GridRequest::Kind::explicit_dims: return "cells";
    case GridRequest::Kind::voxel_size: return "edge";
    }
    return "automatic";
}

// The cell columns (or rows) from `low` to `high`, clamped to the grid (a file outside it still has
// a tile to read it). A millionth of a cell more on each side: a header bound within rounding of
// a cell's face must not lose the tile beyond it; a tile read for nothing costs more than that.
std::pair<std::uint32_t, std::uint32_t> cell_range(double low, double high, double origin, double cell,
                                                   std::uint32_t cells) {
    constexpr double margin = 1e-6;
    const auto clamp = [&](double c) {
        return static_cast<std::uint32_t>(std::clamp(c, 0.0, static_cast<double>(cells - 1)));
    };
    return {clamp(std::floor((low - origin) / cell - margin)), clamp(std::floor((high - origin) / cell + margin))};
}

// A COPC file's nodes, when the file is one a tile can read in part: LAZ by path, in the
// survey's CRS (a node's cube is in the file's coordinates); nullopt otherwise.
std::optional<std::vector<CopcNode>> copc_nodes(const SurveyFile& file) {
    if (!file.compressed || file.transform) return std::nullopt;
    InputStream stream(file.path);
    if (stream.compression() != Compression::none) return std::nullopt;
    const LasHeader header = read_las_header(stream);
    if (!header.compressed) return std::nullopt;
    return read_copc_nodes(file.path, header);
}

} // namespace

std::uint32_t tile_cells_for(double size, double cell) {
    const double cells = std::ceil(size / cell * (1 - 1e-12));
    const std::uint64_t brick = CellGrid::brick_size;
    const auto whole = static_cast<std::uint64_t>(std::min(cells, double(max_grid_cells)));
    return static_cast<std::uint32_t>(
        std::clamp<std::uint64_t>((whole + brick - 1) / brick * brick, brick, max_grid_cells));
}

TilePlan plan_tiles(const std::vector<std::string>& inputs, const BuildOptions& o, double tile_size) {
    if (o.scan_bounds)
        throw Error(ErrorKind::usage,
                    "a plan reads headers only: scanning the points for their bounds cannot be planned (give the "
                    "bounds, or correct the headers)",
                    "scan_bounds");
    if (o.skip_bad_inputs)
        throw Error(ErrorKind::usage,
                    "a plan's tiles must read every input planned: leave out bad inputs before planning instead",
                    "skip_bad_inputs");
    if (!std::isfinite(tile_size) || tile_size < 0)
        throw Error(ErrorKind::usage, "the tile size must be a length, or 0 to choose it from the data", "tile");
    check_read_options(inputs, o);
    for (const std::string& input : inputs)
        if (input == "-")
            throw Error(ErrorKind::usage, "a plan's inputs must be files: every tile job reads them", "inputs");
    RunReport report;
    SurveyStart start = open_survey(inputs, o, report);
    const Survey& survey = start.survey;
    const LasHeader& header = survey.header;

    TilePlan plan;
    plan.grid_request = o.grid;
    plan.bounds = o.bounds;
    plan.crs = o.crs;
    plan.unit = report.unit;
    AccumulateOptions accumulate = start.accumulate;
    if (o.grid.kind == GridRequest::Kind::automatic) // the first grid; merge coarsens it as one machine would
        accumulate.grid = choose_grid(header.point_count, o.bounds.value_or(Bounds{header.min, header.max}),
                                      inputs.size() == 1 ? inputs.front() : std::to_string(inputs.size()) + " files")
                              .request;
    plan.grid = grid_for(header, accumulate);
    const GridSpec& grid = plan.grid;

    if (tile_size > 0) {
        plan.tile_cells = tile_cells_for(tile_size, grid.cell_size);
    } else {
        const double tiles = std::max(1.0, std::ceil(double(header.point_count) / default_points_per_tile));
        const double cells = std::ceil(std::sqrt(double(grid.dims[0]) * grid.dims[1] / tiles));
        plan.tile_cells = tile_cells_for(cells * grid.cell_size, grid.cell_size);
    }
    plan.tile_size = double(plan.tile_cells) * grid.cell_size;

    std::map<std::pair<std::uint32_t, std::uint32_t>, PlannedTile> tiles; // by (y, x)
    // The tiles a box of the survey touches (clamped to the grid: each point has a tile to read it).
    const auto for_tiles = [&](const Vec3& min, const Vec3& max, const auto& visit) {
        const auto [x0, x1] = cell_range(min[0], max[0], grid.origin[0], grid.cell_size, grid.dims[0]);
        const auto [y0, y1] = cell_range(min[1], max[1], grid.origin[1], grid.cell_size, grid.dims[1]);
        for (std::uint32_t ty = y0 / plan.tile_cells; ty <= y1 / plan.tile_cells; ++ty)
            for (std::uint32_t tx = x0 / plan.tile_cells; tx <= x1 / plan.tile_cells; ++tx) {
                PlannedTile& tile = tiles[{ty, tx}];
                tile.x = tx, tile.y = ty;
                visit(tile);
            }
    };
    for (std::size_t i = 0; i < survey.files.size(); ++i) {
        const SurveyFile& file = survey.files[i];
        plan.inputs.push_back(
            {std::filesystem::absolute(file.path).lexically_normal().string(), file.bytes, file.point_count});
        if (file.point_count == 0) continue;
        // A COPC file in the survey's CRS: by its nodes, each a chunk of points within a cube.
        if (const auto nodes = copc_nodes(file)) {
            for (const CopcNode& node : *nodes) {
                Vec3 min = node.cube.min, max = node.cube.max;
                for (int a = 0; a < 2; ++a) // within the header's bounds, unless they miss the node
                    if (file.min[a] <= max[a] && min[a] <= file.max[a])
                        min[a] = std::max(min[a], file.min[a]), max[a] = std::min(max[a], file.max[a]);
                for_tiles(min, max, [&](PlannedTile& tile) {
                    if (tile.inputs.empty() || tile.inputs.back() != i) {
                        tile.inputs.push_back(i);
                        tile.chunks.push_back({i, {}, {}});
                    }
                    tile.chunks.back().offsets.push_back(node.offset);
                    tile.chunks.back().points.push_back(node.points);
                    tile.points += node.points;
                });
            }
            continue;
        }
        for_tiles(file.min, file.max, [&](PlannedTile& tile) {
            tile.inputs.push_back(i);
            tile.points += file.point_count;
        });
    }
    for (auto& [key, tile] : tiles) {
        tile.x_cells = {tile.x * plan.tile_cells, std::min(grid.dims[0], (tile.x + 1) * plan.tile_cells)};
        tile.y_cells = {tile.y * plan.tile_cells, std::min(grid.dims[1], (tile.y + 1) * plan.tile_cells)};
        plan.tiles.push_back(std::move(tile));
    }
    return plan;
}

namespace {

Json plan_json(const TilePlan& plan) {
    Json json;
    json["lasmesh_plan"] = 1;
    Json inputs = Json::array();
    for (const PlannedInput& input : plan.inputs)
        inputs.push_back({{"path", input.path}, {"bytes", input.bytes}, {"points", input.points}});
    json["inputs"] = std::move(inputs);
    const GridRequest& r = plan.grid_request;
    json["grid_request"] = {{"kind", request_kind(r.kind)}, {"dims", r.dims}, {"edge", r.voxel}};
    json["bounds"] = plan.bounds ? Json{{"min", plan.bounds->min}, {"max", plan.bounds->max}} : Json();
    json["crs"] = plan.crs;
    json["grid"] = {{"origin", plan.grid.origin}, {"cell_size", plan.grid.cell_size}, {"dims", plan.grid.dims}};
    json["unit"] = plan.unit;
    json["tile"] = {{"size", plan.tile_size}, {"cells", plan.tile_cells}};
    Json tiles = Json::array();
    for (std::size_t k = 0; k < plan.tiles.size(); ++k) {
        const PlannedTile& t = plan.tiles[k];
        Json tile{{"index", k},         {"x", t.x},
                  {"y", t.y},           {"cells", {t.x_cells[0], t.x_cells[1], t.y_cells[0], t.y_cells[1]}},
                  {"inputs", t.inputs}, {"points", t.points}};
        if (!t.chunks.empty()) {
            Json chunks = Json::array();
            for (const PlannedChunks& c : t.chunks)
                chunks.push_back({{"input", c.input}, {"offsets", c.offsets}, {"points", c.points}});
            tile["copc_chunks"] = std::move(chunks);
        }
        tiles.push_back(std::move(tile));
    }
    json["tiles"] = std::move(tiles);
    return json;
}

} // namespace

void write_plan(TilePlan& plan, const std::string& path) {
    const std::string text = plan_json(plan).dump(1) + "\n";
    OutputFile file(path);
    file.write(text);
    file.commit();
    plan.path = path;
    plan.hash = fnv1a(text);
}

TilePlan read_plan(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_input_error(path, "cannot open this plan (lasmesh plan writes one)");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    const std::string text = bytes.str();
    TilePlan plan;
    plan.path = path;
    plan.hash = fnv1a(text);
    try {
        const nlohmann::json json = nlohmann::json::parse(text);
        if (!json.is_object() || json.value("lasmesh_plan", 0) != 1)
            throw_input_error(path, "not a lasmesh plan (no \"lasmesh_plan\": 1)");
        for (const auto& input : json.at("inputs"))
            plan.inputs.push_back({input.at("path").get<std::string>(), input.at("bytes").get<std::uint64_t>(),
                                   input.at("points").get<std::uint64_t>()});
        const auto& r = json.at("grid_request");
        const std::string kind = r.at("kind").get<std::string>();
        plan.grid_request.kind = kind == "longest" ? GridRequest::Kind::longest_axis
                                 : kind == "cells" ? GridRequest::Kind::explicit_dims
                                 : kind == "edge"  ? GridRequest::Kind::voxel_size
                                                   : GridRequest::Kind::automatic;
        plan.grid_request.dims = r.at("dims").get<std::array<std::uint32_t, 3>>();
        plan.grid_request.voxel = r.at("edge").get<double>();
        if (!json.at("bounds").is_null())
            plan.bounds = Bounds{json.at("bounds").at("min").get<Vec3>(), json.at("bounds").at("max").get<Vec3>()};
        plan.crs = json.at("crs").get<std::string>();
        plan.grid.origin = json.at("grid").at("origin").get<Vec3>();
        plan.grid.cell_size = json.at("grid").at("cell_size").get<double>();
        plan.grid.dims = json.at("grid").at("dims").get<std::array<std::uint32_t, 3>>();
        const auto& d = plan.grid.dims;
        if (std::min({d[0], d[1], d[2]}) == 0 || std::max({d[0], d[1], d[2]}) > max_grid_cells ||
            !within_brick_numbers(plan.grid))
            throw_input_error(path, "its grid of " + std::to_string(plan.grid.dims[0]) + " x " +
                                        std::to_string(plan.grid.dims[1]) + " x " + std::to_string(plan.grid.dims[2]) +
                                        " cells is not one a plan can have (1 to " + std::to_string(max_grid_cells) +
                                        " cells an axis, at most " + std::to_string(max_grid_bricks) +
                                        " bricks): plan again");
        plan.unit = json.at("unit").get<std::string>();
        plan.tile_size = json.at("tile").at("size").get<double>();
        plan.tile_cells = json.at("tile").at("cells").get<std::uint32_t>();
        for (const auto& t : json.at("tiles")) {
            PlannedTile tile;
            tile.x = t.at("x").get<std::uint32_t>(), tile.y = t.at("y").get<std::uint32_t>();
            const auto c = t.at("cells").get<std::array<std::uint32_t, 4>>();
            tile.x_cells = {c[0], c[1]}, tile.y_cells = {c[2], c[3]};
            tile.inputs = t.at("inputs").get<std::vector<std::size_t>>();
            tile.points = t.at("points").get<std::uint64_t>();
            if (t.contains("copc_chunks"))
                for (const auto& c : t.at("copc_chunks")) {
                    PlannedChunks chunks{c.at("input").get<std::size_t>(),
                                         c.at("offsets").get<std::vector<std::uint64_t>>(),
                                         c.at("points").get<std::vector<std::uint64_t>>()};
                    if (!std::binary_search(tile.inputs.begin(), tile.inputs.end(), chunks.input) ||
                        chunks.offsets.empty() || chunks.offsets.size() != chunks.points.size() ||
                        !std::is_sorted(chunks.offsets.begin(), chunks.offsets.end()))
                        throw_input_error(path, "tile " + std::to_string(plan.tiles.size()) +
                                                    "'s COPC chunks of input " + std::to_string(chunks.input) +
                                                    " are not a list of its inputs' chunks");
                    tile.chunks.push_back(std::move(chunks));
                }
            for (const std::size_t i : tile.inputs)
                if (i >= plan.inputs.size())
                    throw_input_error(path, "a tile names input " + std::to_string(i) + " of " +
                                                std::to_string(plan.inputs.size()));
            if (tile.x_cells[0] >= tile.x_cells[1] || tile.x_cells[1] > plan.grid.dims[0] ||
                tile.y_cells[0] >= tile.y_cells[1] || tile.y_cells[1] > plan.grid.dims[1] ||
                tile.x_cells[0] % CellGrid::brick_size || tile.y_cells[0] % CellGrid::brick_size)
                throw_input_error(path,
                                  "tile " + std::to_string(plan.tiles.size()) + "'s cells are not within the grid");
            plan.tiles.push_back(std::move(tile));
        }
    } catch (const nlohmann::json::exception& e) {
        throw_input_error(path, std::string("not a valid plan: ") + e.what());
    }
    if (plan.inputs.empty() || plan.tiles.empty()) throw_input_error(path, "a plan without inputs or tiles");
    return plan;
}

std::vector<std::string> planned_paths(const TilePlan& plan) {
    std::vector<std::string> paths;
    for (const PlannedInput& input : plan.inputs) paths.push_back(input.path);
    return paths;
}

BuildOptions planned_options(const TilePlan& plan, BuildOptions options) {
    options.grid = plan.grid_request, options.bounds = plan.bounds, options.crs = plan.crs;
    options.scan_bounds = false, options.skip_bad_inputs = false;
    return options;
}

SurveyStart open_planned_survey(const TilePlan& plan, const BuildOptions& planned, RunReport& r) {
    SurveyStart opened = open_survey(planned_paths(plan), planned, r);
    for (std::size_t i = 0; i < opened.survey.files.size(); ++i) {
        const SurveyFile& file = opened.survey.files[i];
        const PlannedInput& then = plan.inputs[i];
        if (file.point_count != then.points || file.bytes != then.bytes)
            throw_input_error(file.path, "changed since " + plan.path + " was written (" + std::to_string(then.points) +
                                             " points in " + std::to_string(then.bytes) + " bytes then, " +
                                             std::to_string(file.point_count) + " in " + std::to_string(file.bytes) +
                                             " now): plan again, and run every tile");
    }
    return opened;
}

std::string tiles_folder(const TilePlan& plan) {
    std::filesystem::path p(plan.path);
    const std::string stem = p.extension() == ".json" ? p.stem().string() : p.filename().string();
    return (p.parent_path() / (stem + "-tiles")).string();
}

std::string tile_path(const TilePlan& plan, std::size_t index) {
    return (std::filesystem::path(tiles_folder(plan)) / ("tile-" + std::to_string(index) + ".cells")).string();
}

} // namespace lasmesh
