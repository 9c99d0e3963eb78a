// SPDX-License-Identifier: Apache-2.0
// Grid geometry: from bounds and a request to cubic cells, and from cells to raw-integer ranges.
#include "lasmesh/grid.hpp"
#include "grid/axis_cells.hpp"

#include "lasmesh/error.hpp"
#include "number_text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace lasmesh {

namespace {

[[noreturn]] void usage_error(const std::string& what, const std::string& option) {
    throw Error(ErrorKind::usage, what, option);
}

} // namespace

GridSpec make_grid_spec(const Bounds& bounds, const GridRequest& request) {
    GridSpec grid;
    Vec3 extent;
    for (int a = 0; a < 3; ++a) {
        extent[a] = std::max(0.0, bounds.max[a] - bounds.min[a]);
        if (!std::isfinite(extent[a]))
            usage_error(std::string("the bounds along ") + "XYZ"[a] + " (" + shortest(bounds.min[a]) + " to " +
                            shortest(bounds.max[a]) + ") are too wide to grid; give bounds around the points",
                        "bounds");
    }
    const double longest = std::max({extent[0], extent[1], extent[2]});
    const auto too_many = [](double cells) {
        usage_error("the grid would need " + four_digits(cells) + " cells along one axis, more than " +
                        std::to_string(max_grid_cells) + "; use larger cells, or fewer",
                    "grid");
    };

    // The cells span the bounds with half a cell to spare on each side: points on the bounds
    // (a flat scan's plane, the extreme points) lie inside cells, never on the grid's boundary,
    // where no surface can be contoured.
    switch (request.kind) {
    case GridRequest::Kind::automatic:
        // Choosing needs the point count as well as the bounds (choose_grid); accumulate_cells
        // does that before it comes here.
        usage_error("an automatic grid is chosen from the points' count as well as their bounds (build_mesh "
                    "does it): ask for a number of cells or a cell edge",
                    "grid");
    case GridRequest::Kind::longest_axis:
        if (request.dims[0] > max_grid_cells) too_many(request.dims[0]);
        grid.cell_size = longest / std::max<std::uint32_t>(1, request.dims[0] - 1);
        break;
    case GridRequest::Kind::explicit_dims:
        grid.cell_size = 0;
        for (int a = 0; a < 3; ++a) {
            if (request.dims[a] > max_grid_cells) too_many(request.dims[a]);
            grid.cell_size = std::max(grid.cell_size, extent[a] / std::max<std::uint32_t>(1, request.dims[a] - 1));
        }
        break;
    case GridRequest::Kind::voxel_size: grid.cell_size = request.voxel; break;
    }
    if (!(grid.cell_size > 0)) grid.cell_size = 1; // every extent is zero: cells of one unit

    for (int a = 0; a < 3; ++a) {
        if (request.kind == GridRequest::Kind::explicit_dims) {
            grid.dims[a] = request.dims[a];
        } else if (request.kind == GridRequest::Kind::longest_axis && request.dims[0] == 1) {
            grid.dims[a] = 1; // one cell holds everything
        } else {
            // One cell more than the extent needs (a hair less, so that the longest axis of
            // N cells along the longest axis, exactly N - 1 cells long, gets N), the extent centred in them.
            const double cells = std::ceil(extent[a] / grid.cell_size + 1 - 1e-9);
            if (!(cells <= max_grid_cells)) too_many(cells);
            grid.dims[a] = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(cells));
        }
        grid.origin[a] = bounds.min[a] - (grid.dims[a] * grid.cell_size - extent[a]) / 2;
    }
    if (!within_brick_numbers(grid))
        usage_error("the grid " + std::to_string(grid.dims[0]) + " x " + std::to_string(grid.dims[1]) + " x " +
                        std::to_string(grid.dims[2]) + " would hold more than " + std::to_string(max_grid_bricks) +
                        " bricks of 4 x 4 x 4 cells; use larger cells, or fewer",
                    "grid");
    return grid;
}

std::int64_t AxisCells::cell_of(std::int64_t raw) const {
    if (raw < starts.front() || raw >= starts.back()) return -1;
    return std::upper_bound(starts.begin(), starts.end(), raw) - starts.begin() - 1;
}

bool within_brick_numbers(const GridSpec& grid) {
    std::uint64_t bricks = 1;
    for (const std::uint32_t d : grid.dims) bricks *= (std::uint64_t{d} + 3) / 4;
    return bricks <= max_grid_bricks;
}

AxisCells axis_cells(const GridSpec& grid, int axis, double scale, double offset) {
    // Raw integers beyond int32 never occur, so clamping there keeps every start comparable.
    constexpr std::int64_t lowest = std::numeric_limits<std::int32_t>::min();
    constexpr std::int64_t past_highest = std::int64_t{std::numeric_limits<std::int32_t>::max()} + 1;
    auto world = [&](std::int64_t raw) { return static_cast<double>(raw) * scale + offset; };
    // Smallest raw value whose coordinate passes `limit` (>= limit, or > limit when `strictly`).
    // world() never decreases as raw grows (scale > 0, rounding is monotonic), so bisection finds
    // it in 32 steps; walking from an estimate took 2^31 steps when the offset dwarfs the scale.
    auto first_raw_beyond = [&](double limit, bool strictly) {
        auto passes = [&](std::int64_t raw) { return strictly ? world(raw) > limit : world(raw) >= limit; };
        if (passes(lowest)) return lowest;
        std::int64_t below = lowest, above = past_highest; // !passes(below); above: passes, or none does
        while (above - below > 1) {
            const std::int64_t middle = below + (above - below) / 2;
            (passes(middle) ? above : below) = middle;
        }
        return above;
    };

    const std::uint32_t n = grid.dims[axis];
    AxisCells cells;
    cells.starts.resize(n + 1);
    for (std::uint32_t i = 0; i < n; ++i)
        cells.starts[i] = first_raw_beyond(grid.origin[axis] + i * grid.cell_size, false);
    // Closed upper face: the end is the first raw value strictly above it.
    cells.starts[n] = first_raw_beyond(grid.origin[axis] + n * grid.cell_size, true);
    return cells;
}

} // namespace lasmesh
