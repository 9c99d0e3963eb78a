// SPDX-License-Identifier: Apache-2.0
// coarsen_grid and coarsen_while_sparse: the automatic grid's second look, at the accumulated counts.
// Merging 2 x 2 x 2 cells keeps every sum exact (counts and colours add; position sums move to
// the larger cell's start), so a coarsened grid is the grid that accumulating at twice the cell
// would give, without reading the input again.
#include "grid/auto_grid.hpp"
#include "grid/cell_sums.hpp"

#include <algorithm>
#include <bit>
#include <string>
#include <tuple>

namespace lasmesh {

CellGrid coarsen_grid(const CellGrid& fine) {
    constexpr std::int64_t size = CellGrid::brick_size;
    CellGrid coarse;
    coarse.spec = fine.spec;
    coarse.spec.cell_size = 2 * fine.spec.cell_size;
    for (int a = 0; a < 3; ++a) {
        coarse.spec.dims[a] = (fine.spec.dims[a] + 1) / 2;
        // Every other start of the fine cells, and the fine grid's end: the same points inside.
        const std::vector<std::int64_t>& starts = fine.axes[a].starts;
        for (std::size_t i = 0; i + 1 < starts.size(); i += 2) coarse.axes[a].starts.push_back(starts[i]);
        coarse.axes[a].starts.push_back(starts.back());
        coarse.bricks[a] = static_cast<std::uint32_t>((coarse.spec.dims[a] + size - 1) / size);
    }
    coarse.color = fine.color;
    coarse.moments = fine.moments;
    coarse.scale = fine.scale;
    coarse.offset = fine.offset;
    coarse.points_read = fine.points_read;
    coarse.points_outside = fine.points_outside;
    coarse.color_max_word = fine.color_max_word;

    // The coarse bricks: fine brick (x, y, z) falls in coarse brick (x / 2, y / 2, z / 2). Each
    // coarse brick is summed from its (up to 8) fine bricks, then keeps its occupied cells.
    auto coarse_key = [&](std::uint64_t key) {
        const std::uint64_t x = key % fine.bricks[0], y = key / fine.bricks[0] % fine.bricks[1],
                            z = key / fine.bricks[0] / fine.bricks[1];
        return (z / 2 * coarse.bricks[1] + y / 2) * coarse.bricks[0] + x / 2;
    };
    std::vector<std::pair<std::uint64_t, std::size_t>> fine_of_coarse; // (coarse key, fine brick)
    fine_of_coarse.reserve(fine.brick_keys.size());
    for (std::size_t b = 0; b < fine.brick_keys.size(); ++b)
        fine_of_coarse.emplace_back(coarse_key(fine.brick_keys[b]), b);
    std::sort(fine_of_coarse.begin(), fine_of_coarse.end());
    std::array<CellSums, CellGrid::brick_cells> sums{};
    for (std::size_t i = 0; i < fine_of_coarse.size();) {
        const std::uint64_t key = fine_of_coarse[i].first;
        sums.fill(CellSums{});
        for (; i < fine_of_coarse.size() && fine_of_coarse[i].first == key; ++i) {
            const std::size_t b = fine_of_coarse[i].second;
            std::uint64_t record = fine.brick_first[b];
            for (std::uint64_t mask = fine.brick_masks[b]; mask != 0; mask &= mask - 1, ++record) {
                const CellSums& from = fine.cells[record];
                const auto cell = fine.cell_in_brick(fine.brick_keys[b], static_cast<unsigned>(std::countr_zero(mask)));
                constexpr std::int64_t m = size - 1;
                CellSums& to = sums[static_cast<std::size_t>(
                    (((cell[2] >> 1) & m) * size + ((cell[1] >> 1) & m)) * size + ((cell[0] >> 1) & m))];
                to.count += from.count;
                std::array<std::uint64_t, 3> shift{};
                for (int a = 0; a < 3; ++a) {
                    // Position sums count from the cell's first raw value: the fine cell starts later.
                    shift[a] =
                        static_cast<std::uint64_t>(fine.axes[a].starts[static_cast<std::size_t>(cell[a])] -
                                                   coarse.axes[a].starts[static_cast<std::size_t>(cell[a] >> 1)]);
                    to.position[a] += from.position[a] + from.count * shift[a];
                    to.color[a] += from.color[a];
                }
                // sum (p + s)(q + t) = sum pq + t sum p + s sum q + n s t, modulo 2^64 as the device's.
                for (std::size_t k = 0; k < 6; ++k) {
                    const int a = moment_axes[k][0], b = moment_axes[k][1];
                    to.moments[k] += from.moments[k] + shift[b] * from.position[a] + shift[a] * from.position[b] +
                                     from.count * shift[a] * shift[b];
                }
            }
        }
        coarse.brick_keys.push_back(key);
        coarse.brick_first.push_back(coarse.cells.size());
        coarse.brick_masks.push_back(coarse.append_occupied(sums));
    }
    coarse.index_bricks();
    return coarse;
}

CellGrid sum_of_parts(std::vector<CellGrid>&& parts) {
    if (parts.empty()) return {};
    CellGrid whole = empty_like(parts.front());
    std::vector<std::tuple<std::uint64_t, std::size_t, std::size_t>> bricks; // key, part, brick
    for (std::size_t p = 0; p < parts.size(); ++p)
        for (std::size_t b = 0; b < parts[p].brick_keys.size(); ++b) bricks.emplace_back(parts[p].brick_keys[b], p, b);
    std::sort(bricks.begin(), bricks.end());
    std::array<CellSums, CellGrid::brick_cells> sums{};
    for (std::size_t i = 0; i < bricks.size();) {
        const std::uint64_t key = std::get<0>(bricks[i]);
        sums.fill(CellSums{});
        for (; i < bricks.size() && std::get<0>(bricks[i]) == key; ++i) {
            const CellGrid& part = parts[std::get<1>(bricks[i])];
            const std::size_t b = std::get<2>(bricks[i]);
            std::uint64_t record = part.brick_first[b];
            for (std::uint64_t mask = part.brick_masks[b]; mask != 0; mask &= mask - 1, ++record) {
                const CellSums& from = part.cells[record];
                CellSums& to = sums[static_cast<std::size_t>(std::countr_zero(mask))];
                to.count += from.count;
                for (int a = 0; a < 3; ++a) to.position[a] += from.position[a], to.color[a] += from.color[a];
                for (std::size_t k = 0; k < 6; ++k) to.moments[k] += from.moments[k];
            }
        }
        whole.brick_keys.push_back(key);
        whole.brick_first.push_back(whole.cells.size());
        whole.brick_masks.push_back(whole.append_occupied(sums));
    }
    whole.index_bricks();
    return whole;
}

std::string coarsen_while_sparse(CellGrid& grid, std::uint64_t min_median) {
    int merged = 0;
    std::uint64_t median = grid.median_count();
    while (median > 0 && median < min_median &&
           std::max({grid.spec.dims[0], grid.spec.dims[1], grid.spec.dims[2]}) > auto_grid_min_cells) {
        grid = coarsen_grid(grid);
        median = grid.median_count();
        ++merged;
    }
    if (merged == 0) return {};
    return "then " + std::to_string(1 << merged) + " times coarser: the occupied cells held a median of fewer than " +
           std::to_string(min_median) + " points, now " + std::to_string(median);
}

int coarsen_while_single_points(CellGrid& grid) {
    int merged = 0;
    while (grid.median_count() == 1 &&
           std::max({grid.spec.dims[0], grid.spec.dims[1], grid.spec.dims[2]}) > auto_grid_min_cells) {
        grid = coarsen_grid(grid);
        ++merged;
    }
    return merged;
}

void finish_chosen_grid(CellGrid& grid, const GridChoice& choice) {
    const std::string coarsened = coarsen_while_sparse(grid, choice.min_median);
    grid.grid_reason = "auto: " + choice.reason + (coarsened.empty() ? "" : "; " + coarsened);
}

} // namespace lasmesh
