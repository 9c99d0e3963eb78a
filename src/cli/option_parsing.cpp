// SPDX-License-Identifier: Apache-2.0
// Option text parsers: strict (the whole text must be used) and quoting the text in each error.
#include "option_parsing.hpp"

#include "lasmesh/error.hpp"
#include "number_text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace lasmesh::cli {

namespace {

[[noreturn]] void usage_error(const std::string& what) {
    throw Error(ErrorKind::usage, what);
}

std::uint32_t parse_cells(const std::string& part, const std::string& whole) {
    std::uint32_t value = 0;
    auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (ec != std::errc() || end != part.data() + part.size() || value == 0 || value > max_grid_cells)
        usage_error("--grid \"" + whole + "\": expected N or NXxNYxNZ with whole numbers from 1 to " +
                    std::to_string(max_grid_cells) + " (cells per axis)");
    return value;
}

} // namespace

GridRequest parse_grid_request(const std::string& text) {
    GridRequest request;
    const std::size_t first = text.find('x');
    if (first == std::string::npos) {
        request.kind = GridRequest::Kind::longest_axis;
        request.dims = {parse_cells(text, text), 0, 0};
        return request;
    }
    const std::size_t second = text.find('x', first + 1);
    if (second == std::string::npos || text.find('x', second + 1) != std::string::npos)
        usage_error("--grid \"" + text + "\": expected N or NXxNYxNZ, e.g. 256 or 512x256x128");
    request.kind = GridRequest::Kind::explicit_dims;
    request.dims = {parse_cells(text.substr(0, first), text),
                    parse_cells(text.substr(first + 1, second - first - 1), text),
                    parse_cells(text.substr(second + 1), text)};
    return request;
}

GridRequest voxel_request(double cell_size) {
    if (!(cell_size > 0) || !std::isfinite(cell_size))
        usage_error("--voxel " + shortest(cell_size) + ": the cell edge must be a positive number");
    GridRequest request;
    request.kind = GridRequest::Kind::voxel_size;
    request.voxel = cell_size;
    return request;
}

Bounds parse_bounds(const std::string& text) {
    const std::string expected = "--bounds \"" + text + "\": expected six numbers minx,miny,minz,maxx,maxy,maxz";
    std::vector<double> values;
    std::size_t at = 0;
    while (at <= text.size()) {
        std::size_t comma = std::min(text.find(',', at), text.size());
        double value = 0;
        auto [end, ec] = std::from_chars(text.data() + at, text.data() + comma, value);
        if (comma == at || ec != std::errc() || end != text.data() + comma || !std::isfinite(value))
            usage_error(expected);
        values.push_back(value);
        at = comma + 1;
    }
    if (values.size() != 6) usage_error(expected);
    Bounds b;
    for (int a = 0; a < 3; ++a) {
        b.min[a] = values[a];
        b.max[a] = values[a + 3];
        if (b.min[a] > b.max[a]) usage_error("--bounds \"" + text + "\": a minimum is larger than its maximum");
    }
    return b;
}

double parse_iso(const std::string& text) {
    if (text == "auto") return -1;
    double value = 0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !(value >= 0) || !std::isfinite(value))
        usage_error("--iso \"" + text + "\": expected a number of points per cell (>= 0) or auto");
    return value;
}

VertexPlacement parse_placement(const std::string& text) {
    if (text == "surface") return VertexPlacement::surface;
    if (text == "iso") return VertexPlacement::iso;
    usage_error("--placement \"" + text + "\": expected surface or iso");
}

MinPiece parse_min_piece(const std::string& text) {
    const bool relative = !text.empty() && text.back() == '%';
    const std::string number = relative ? text.substr(0, text.size() - 1) : text;
    double value = 0;
    const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), value);
    if (number.empty() || ec != std::errc{} || end != number.data() + number.size() || !std::isfinite(value) ||
        value < 0 || (relative && value > 100))
        usage_error("--min-piece \"" + text +
                    "\": expected a percentage of the mesh diagonal (e.g. 5%), a length, or 0");
    return {relative ? value / 100 : value, relative};
}

SimplifyRequest parse_simplify(const std::string& text) {
    const std::string unit = "cell";
    const bool in_cells = text.size() > unit.size() && text.compare(text.size() - unit.size(), unit.size(), unit) == 0;
    const std::string number = in_cells ? text.substr(0, text.size() - unit.size()) : text;
    double value = 0;
    const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), value);
    if (number.empty() || ec != std::errc{} || end != number.data() + number.size() || !std::isfinite(value) ||
        value < 0)
        usage_error("--simplify \"" + text +
                    "\": expected a length (in the unit of the coordinate system), a fraction of a cell (e.g. "
                    "0.5cell), or 0 for none");
    SimplifyRequest request;
    request.error = value;
    request.in_cells = in_cells;
    return request;
}

GltfCompression parse_glb_compression(const std::string& text) {
    if (text == "none") return GltfCompression::none;
    if (text == "draco") return GltfCompression::draco;
    usage_error("--glb-compression \"" + text + "\": expected none or draco");
}

GltfOrigin parse_glb_origin(const std::string& text) {
    if (text == "extras") return GltfOrigin::extras;
    if (text == "node") return GltfOrigin::node;
    usage_error("--glb-origin \"" + text + "\": expected extras or node");
}

CLI::Validator positive_number() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            double value = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
            if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !(value > 0) ||
                !std::isfinite(value))
                return "expected a positive number, got \"" + text + "\"";
            return "";
        },
        "POSITIVE");
}

std::string flag_hint(const Error& error) {
    static const std::map<std::string, std::string> flags{
        {"outputs", "-o"},
        {"report", "--report"},
        {"scan_bounds", "--scan-bounds"},
        {"placement", "--placement"},
        {"iso", "--iso"},
        {"simplify", "--simplify"},
        {"min_piece", "--min-piece"},
        {"threads", "--threads"},
        {"grid", "--grid"},
        {"bounds", "--bounds"},
        {"surface", "--surface"},
        {"max_memory", "--max-memory"},
        {"device", "--device"},
        {"skip_bad_inputs", "--skip-bad-inputs"},
        {"refine_thin", "--refine-thin"},
        {"crs", "--crs"},
        {"index", "--index"},
        {"tile", "--tile"},
    };
    std::vector<std::string> named;
    std::stringstream options(error.option());
    for (std::string option; std::getline(options, option, ',');)
        if (const auto flag = flags.find(option); flag != flags.end()) named.push_back(flag->second);
    if (named.empty()) return {};
    std::string hint = " (";
    for (std::size_t i = 0; i < named.size(); ++i) hint += (i ? " or " : "") + named[i];
    if (!error.suggestion().empty()) hint += " " + error.suggestion();
    if (error.option() == "device") hint += "; `lasmesh devices` lists them";
    return hint + ")";
}

CLI::Validator whole_number(std::uint64_t lowest, std::uint64_t highest) {
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            std::uint64_t value = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
            if (text.empty() || ec != std::errc() || end != text.data() + text.size() || value < lowest ||
                value > highest)
                return "expected a whole number from " + std::to_string(lowest) + " to " + std::to_string(highest) +
                       ", got \"" + text + "\"";
            return "";
        },
        std::to_string(lowest) + "-" + std::to_string(highest));
}

CLI::Validator one_of(const std::vector<std::string>& words) {
    std::string list;
    for (std::size_t i = 0; i < words.size(); ++i)
        list += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
    std::string bar;
    for (std::size_t i = 0; i < words.size(); ++i) bar += (i ? "|" : "") + words[i];
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            if (std::find(words.begin(), words.end(), text) != words.end()) return "";
            return "expected " + list + ", got \"" + text + "\"";
        },
        bar);
}

SurfaceKind parse_surface(const std::string& text) {
    if (text == "sheet") return SurfaceKind::sheet;
    if (text == "closed") return SurfaceKind::closed;
    usage_error("--surface \"" + text + "\": expected sheet or closed");
}

} // namespace lasmesh::cli
