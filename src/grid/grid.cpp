// Grid geometry: from bounds and a request to cubic cells, and from cells to raw-integer ranges.
#include "lasmesh/grid/grid.hpp"

#include "lasmesh/error.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace lasmesh {

namespace {

[[noreturn]] void usage_error(const std::string& what) { throw Error(ErrorKind::usage, what); }

std::uint32_t parse_cells(const std::string& part, const std::string& whole) {
    std::uint32_t value = 0;
    auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (ec != std::errc() || end != part.data() + part.size() || value == 0 || value > 65536)
        usage_error("--grid \"" + whole + "\": expected N or NXxNYxNZ with whole numbers from 1 to 65536");
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
    request.dims = {parse_cells(text.substr(0, first), text), parse_cells(text.substr(first + 1, second - first - 1), text),
                    parse_cells(text.substr(second + 1), text)};
    return request;
}

GridRequest voxel_request(double cell_size) {
    if (!(cell_size > 0) || !std::isfinite(cell_size))
        usage_error("--voxel " + std::to_string(cell_size) + ": the cell edge must be a positive number");
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
        if (comma == at || ec != std::errc() || end != text.data() + comma || !std::isfinite(value)) usage_error(expected);
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

GridSpec make_grid_spec(const Bounds& bounds, const GridRequest& request) {
    GridSpec grid;
    grid.origin = bounds.min;
    Vec3 extent;
    for (int a = 0; a < 3; ++a) extent[a] = std::max(0.0, bounds.max[a] - bounds.min[a]);
    const double longest = std::max({extent[0], extent[1], extent[2]});

    switch (request.kind) {
    case GridRequest::Kind::longest_axis: grid.cell_size = longest / request.dims[0]; break;
    case GridRequest::Kind::explicit_dims:
        grid.cell_size = 0;
        for (int a = 0; a < 3; ++a) grid.cell_size = std::max(grid.cell_size, extent[a] / request.dims[a]);
        break;
    case GridRequest::Kind::voxel_size: grid.cell_size = request.voxel; break;
    }
    if (!(grid.cell_size > 0)) grid.cell_size = 1; // every extent is zero: one cell of one unit

    for (int a = 0; a < 3; ++a) {
        if (request.kind == GridRequest::Kind::explicit_dims) {
            grid.dims[a] = request.dims[a];
            continue;
        }
        // The cells needed to reach the upper bound; the last cell is closed at its upper face.
        const double cells = std::ceil(extent[a] / grid.cell_size);
        if (!(cells <= 65536)) usage_error("the grid would need " + std::to_string(cells) +
                                           " cells along one axis; use a larger --voxel or a smaller --grid");
        grid.dims[a] = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(cells));
    }
    return grid;
}

std::int64_t AxisCells::cell_of(std::int64_t raw) const {
    if (raw < starts.front() || raw >= starts.back()) return -1;
    return std::upper_bound(starts.begin(), starts.end(), raw) - starts.begin() - 1;
}

AxisCells axis_cells(const GridSpec& grid, int axis, double scale, double offset) {
    // Raw integers beyond int32 never occur, so clamping there keeps every start comparable.
    constexpr std::int64_t lowest = std::numeric_limits<std::int32_t>::min();
    constexpr std::int64_t past_highest = std::int64_t{std::numeric_limits<std::int32_t>::max()} + 1;
    auto world = [&](std::int64_t raw) { return static_cast<double>(raw) * scale + offset; };
    // Smallest raw value whose coordinate passes `limit` (>= limit, or > limit when `strictly`).
    auto first_raw_beyond = [&](double limit, bool strictly) {
        auto passes = [&](std::int64_t raw) { return strictly ? world(raw) > limit : world(raw) >= limit; };
        double guess = std::ceil((limit - offset) / scale);
        if (!(guess > lowest)) return lowest;
        if (!(guess < past_highest)) return past_highest;
        auto raw = static_cast<std::int64_t>(guess);
        while (raw > lowest && passes(raw - 1)) --raw;
        while (raw < past_highest && !passes(raw)) ++raw;
        return raw;
    };

    const std::uint32_t n = grid.dims[axis];
    AxisCells cells;
    cells.starts.resize(n + 1);
    for (std::uint32_t i = 0; i < n; ++i) cells.starts[i] = first_raw_beyond(grid.origin[axis] + i * grid.cell_size, false);
    // Closed upper face: the end is the first raw value strictly above it.
    cells.starts[n] = first_raw_beyond(grid.origin[axis] + n * grid.cell_size, true);
    return cells;
}

} // namespace lasmesh
