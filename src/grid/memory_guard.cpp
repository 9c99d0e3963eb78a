// SPDX-License-Identifier: Apache-2.0
// The memory guard of accumulate_cells (see memory_guard.hpp), and memory_need.
#include "memory_guard.hpp"

#include "lasmesh/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lasmesh {

namespace {

// The largest N along the longest axis for which `fits(grid)` holds (memory grows with N).
template <class Fits>
std::uint32_t largest_fitting_grid(const LasHeader& header, const AccumulateOptions& options, std::uint32_t upper,
                                   Fits fits) {
    std::uint32_t lo = 0, hi = upper;
    while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo + 1) / 2;
        AccumulateOptions trial = options;
        trial.grid = GridRequest{GridRequest::Kind::longest_axis, {mid, 0, 0}, 0};
        if (fits(grid_for(header, trial)))
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

std::uint32_t longest_dim(const GridSpec& g) {
    return std::max({g.dims[0], g.dims[1], g.dims[2]});
}

} // namespace

std::string mib(std::uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", bytes / 1048576.0);
    return text;
}

std::string dims_text(const GridSpec& g) {
    return std::to_string(g.dims[0]) + "x" + std::to_string(g.dims[1]) + "x" + std::to_string(g.dims[2]);
}

std::uint64_t cell_words(bool color) {
    return color ? 16 : moment_word(color) + 6;
}

std::uint64_t moment_word(bool color) {
    return color ? 6 : 4;
}

std::uint64_t cell_sums(bool color) {
    return color ? 13 : 10;
}

std::array<std::uint32_t, 3> brick_dims(const GridSpec& grid) {
    std::array<std::uint32_t, 3> b{};
    for (int a = 0; a < 3; ++a)
        b[a] = static_cast<std::uint32_t>((grid.dims[a] + CellGrid::brick_size - 1) / CellGrid::brick_size);
    return b;
}

std::uint64_t brick_count(const GridSpec& grid) {
    const auto b = brick_dims(grid);
    return std::uint64_t{b[0]} * b[1] * b[2];
}

std::string exceeded(const MemoryNeed& need, const MemoryLimits& limits, const std::string& what) {
    if (need.largest_buffer > limits.max_alloc)
        return what + " needs " + mib(need.largest_buffer) + ", more than the device's largest allocation (" +
               mib(limits.max_alloc) + ")";
    if (need.device_bytes > limits.global_memory)
        return "it needs " + mib(need.device_bytes) + " of device memory, more than the device has (" +
               mib(limits.global_memory) + ")";
    if (limits.max_memory && need.device_bytes + need.host_bytes + limits.in_use > limits.max_memory)
        return "it needs " + mib(need.device_bytes + need.host_bytes) + " on host and device together" +
               (limits.in_use ? " besides the " + mib(limits.in_use) + " in use before reading" : std::string()) +
               ", more than the memory limit (" + mib(limits.max_memory) + ")";
    return {};
}

void check_index_memory(const LasHeader& header, const AccumulateOptions& options, const GridSpec& grid,
                        std::uint64_t slice_bytes, const MemoryLimits& limits) {
    const std::string problem = exceeded(memory_need(grid, slice_bytes), limits, "the brick index");
    if (problem.empty()) return;
    const std::uint32_t fit = largest_fitting_grid(header, options, longest_dim(grid), [&](const GridSpec& g) {
        return exceeded(memory_need(g, slice_bytes), limits, "").empty();
    });
    throw Error(ErrorKind::usage,
                "the grid " + dims_text(grid) + " (" + std::to_string(grid.cell_count()) + " cells) does not fit: " +
                    problem + (fit > 0 ? "; a grid of " + std::to_string(fit) + " cells would fit" : ""),
                "grid", fit > 0 ? std::to_string(fit) : "");
}

// Assumes the surface's bricks fall with the square of the grid.
[[noreturn]] void pool_too_large(const LasHeader& header, const GridSpec& grid, const std::string& problem,
                                 std::uint64_t bricks_used, std::uint64_t points_read, std::uint64_t available_bytes,
                                 double cost_per_brick_byte) {
    // A scan in acquisition order meets new bricks all along; a random order meets most of them
    // early. Between the two: at most twice the bricks seen so far.
    const double seen = std::max<double>(1, static_cast<double>(points_read)) / std::max<double>(1, header.point_count);
    const double growth = std::min(2.0, 1 / std::min(1.0, seen));
    const double projected =
        static_cast<double>(bricks_used * brick_device_bytes(has_color(header))) * growth * cost_per_brick_byte;
    const double shrink = std::sqrt(static_cast<double>(available_bytes) / std::max(1.0, projected));
    const auto fit = static_cast<std::uint32_t>(std::floor(longest_dim(grid) * std::min(0.9, shrink * 0.9)));
    throw Error(ErrorKind::usage,
                "the grid " + dims_text(grid) + " does not fit: after " + std::to_string(points_read) + " of " +
                    std::to_string(header.point_count) + " points its surface fills " + std::to_string(bricks_used) +
                    " bricks and " + problem +
                    (fit > 0 ? "; a grid of " + std::to_string(fit) + " cells would fit" : "") +
                    " (nothing was written)",
                "grid", fit > 0 ? std::to_string(fit) : "");
}

std::uint64_t first_chunk_bytes(const GridSpec& grid) {
    return std::min<std::uint64_t>(1024, brick_count(grid)) * CellGrid::brick_cells * cell_words(true) * 4;
}

MemoryNeed memory_need(const GridSpec& grid, std::uint64_t slice_bytes) {
    MemoryNeed need;
    const std::uint64_t index_bytes = brick_count(grid) * 4;
    need.largest_buffer = index_bytes;
    // The index, the slices, the lists of points deferred and of bricks new in a slice (at most
    // one per record of 20 bytes or more), and the pool's first chunk (up to 1024 bricks).
    need.device_bytes = index_bytes + slice_buffers * slice_bytes + 2 * (slice_bytes / 4) + first_chunk_bytes(grid);
    // The host keeps a table of the occupied bricks only (counted with the pool); the slices are
    // mapped device memory.
    need.host_bytes = 0;
    return need;
}

} // namespace lasmesh
