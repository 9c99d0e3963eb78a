// SPDX-License-Identifier: Apache-2.0
// CellGrid's cell arithmetic (occupancy, fullest and median cell, mean colour, centroid) and the grid a header asks
// for.
#include "grid/cell_sums.hpp"

#include "memory_guard.hpp"

#include <algorithm>
#include <bit>
#include <vector>

namespace lasmesh {

CellGrid empty_like(const CellGrid& grid) {
    CellGrid part;
    part.spec = grid.spec, part.axes = grid.axes, part.scale = grid.scale, part.offset = grid.offset;
    part.bricks = grid.bricks, part.color = grid.color, part.moments = grid.moments;
    part.color_max_word = grid.color_max_word;
    return part;
}

void append_brick(CellGrid& part, std::uint64_t key, std::uint64_t mask, const CellSums* cells) {
    part.brick_keys.push_back(key);
    part.brick_masks.push_back(mask);
    part.brick_first.push_back(part.cells.size());
    part.cells.insert(part.cells.end(), cells, cells + std::popcount(mask));
}

bool brick_within(std::uint64_t key, const std::array<std::uint32_t, 3>& bricks, std::int64_t x0, std::int64_t x1,
                  std::int64_t y0, std::int64_t y1) {
    const auto b = static_cast<std::int64_t>(CellGrid::brick_size);
    const auto bx = static_cast<std::int64_t>(key % bricks[0]),
               by = static_cast<std::int64_t>(key / bricks[0] % bricks[1]);
    return (bx + 1) * b > x0 && bx * b < x1 && (by + 1) * b > y0 && by * b < y1;
}

CellGrid bricks_within(const CellGrid& grid, std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1) {
    CellGrid part = empty_like(grid);
    for (std::size_t k = 0; k < grid.brick_keys.size(); ++k)
        if (brick_within(grid.brick_keys[k], grid.bricks, x0, x1, y0, y1))
            append_brick(part, grid.brick_keys[k], grid.brick_masks[k], grid.cells.data() + grid.brick_first[k]);
    part.index_bricks();
    return part;
}

BrickTable::BrickTable(const std::vector<std::uint64_t>& keys) {
    std::size_t capacity = 16; // at most half full: short probes
    while (capacity < 2 * keys.size()) capacity *= 2;
    shift_ = 64 - std::countr_zero(capacity);
    keys_.assign(capacity, empty);
    values_.assign(capacity, 0);
    const std::size_t mask = capacity - 1;
    for (std::size_t i = 0; i < keys.size(); ++i) {
        std::size_t at = slot(keys[i]);
        while (keys_[at] != empty) at = (at + 1) & mask;
        keys_[at] = keys[i];
        values_[at] = static_cast<std::uint32_t>(i + 1);
    }
}

std::uint64_t brick_device_bytes(bool has_color) {
    return CellGrid::brick_cells * cell_words(has_color) * 4;
}

std::uint64_t CellGrid::append_occupied(const std::array<CellSums, brick_cells>& brick) {
    std::uint64_t mask = 0;
    for (std::size_t k = 0; k < brick.size(); ++k)
        if (brick[k].count > 0) {
            mask |= std::uint64_t{1} << k;
            cells.push_back(brick[k]);
        }
    return mask;
}

std::uint64_t CellGrid::occupied_cells() const {
    return cells.size();
}

std::uint64_t CellGrid::median_count() const {
    if (cells.empty()) return 0;
    std::vector<std::uint64_t> counts;
    counts.reserve(cells.size());
    for (const CellSums& cell : cells) counts.push_back(cell.count);
    const auto middle = counts.begin() + static_cast<std::ptrdiff_t>(counts.size() / 2);
    std::nth_element(counts.begin(), middle, counts.end());
    return *middle;
}

std::uint64_t CellGrid::fullest_cell() const {
    std::uint64_t fullest = 0;
    for (const CellSums& cell : cells) fullest = std::max(fullest, cell.count);
    return fullest;
}

std::uint64_t CellGrid::host_bytes() const {
    return brick_table.bytes() + brick_keys.size() * 3 * sizeof(std::uint64_t) + cells.size() * sizeof(CellSums);
}

Rgb8 CellGrid::mean_color(const CellSums& cell) const {
    const std::uint64_t n = cell.count;
    if (n == 0 || !has_color()) return {0, 0, 0};
    // Rounded integer division; 128-bit so no count or sum can overflow.
    const unsigned __int128 divisor = static_cast<unsigned __int128>(n) * (color_is_16bit() ? 257 : 1);
    auto mean = [&](std::uint64_t sum) {
        return static_cast<std::uint8_t>((2 * static_cast<unsigned __int128>(sum) + divisor) / (2 * divisor));
    };
    return {mean(cell.color[0]), mean(cell.color[1]), mean(cell.color[2])};
}

Vec3 CellGrid::centroid(const std::array<std::int64_t, 3>& cell, const CellSums& sums) const {
    Vec3 p{};
    for (int a = 0; a < 3; ++a) {
        const double raw =
            static_cast<double>(axes[a].starts[cell[a]]) +
            static_cast<double>(sums.position[a]) / static_cast<double>(std::max<std::uint64_t>(1, sums.count));
        p[a] = raw * scale[a] + offset[a] - spec.origin[a];
    }
    return p;
}

bool CellGrid::moments_exact() const {
    if (!moments) return false;
    unsigned __int128 widest = 0;
    for (const AxisCells& axis : axes)
        for (std::size_t i = 0; i + 1 < axis.starts.size(); ++i)
            widest = std::max(widest, static_cast<unsigned __int128>(axis.starts[i + 1] - axis.starts[i]));
    const unsigned __int128 fullest = fullest_cell();
    return widest < (std::uint64_t{1} << 32) && fullest * widest * widest < (static_cast<unsigned __int128>(1) << 64);
}

std::array<double, 6> CellGrid::scatter(const CellSums& sums) const {
    std::array<double, 6> s{};
    if (sums.count == 0) return s;
    const double n = static_cast<double>(sums.count);
    for (std::size_t k = 0; k < 6; ++k) {
        const int a = moment_axes[k][0], b = moment_axes[k][1];
        const double raw = static_cast<double>(sums.moments[k]) -
                           static_cast<double>(sums.position[a]) * static_cast<double>(sums.position[b]) / n;
        s[k] = raw * scale[a] * scale[b];
    }
    return s;
}

GridSpec grid_for(const LasHeader& header, const AccumulateOptions& options) {
    if (options.spec) return *options.spec;
    return make_grid_spec(options.bounds.value_or(Bounds{header.min, header.max}), options.grid);
}

} // namespace lasmesh
