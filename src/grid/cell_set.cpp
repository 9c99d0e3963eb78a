// SPDX-License-Identifier: Apache-2.0
#include "grid/cell_set.hpp"

#include <algorithm>
#include <utility>

namespace lasmesh {

CellSet::CellSet(const std::vector<std::uint64_t>& keys, const std::array<std::int64_t, 3>& dims,
                 std::uint64_t bitmap_bricks_limit) {
    constexpr int b = CellGrid::brick_bits;
    constexpr std::uint64_t m = CellGrid::brick_size - 1;
    std::array<std::uint64_t, 3> count{};
    for (int a = 0; a < 3; ++a) count[a] = (std::uint64_t(dims[a]) + m) >> b;
    bricks_ = {count[0], count[1]};
    // Each cell's brick and bit, in the order of the bricks.
    std::vector<std::pair<std::uint64_t, std::uint64_t>> cells;
    cells.reserve(keys.size());
    for (const std::uint64_t key : keys) {
        const std::uint64_t x = key % std::uint64_t(dims[0]), y = key / std::uint64_t(dims[0]) % std::uint64_t(dims[1]),
                            z = key / std::uint64_t(dims[0]) / std::uint64_t(dims[1]);
        cells.emplace_back(((z >> b) * count[1] + (y >> b)) * count[0] + (x >> b),
                           std::uint64_t{1} << (((((z & m) << b) + (y & m)) << b) + (x & m)));
    }
    std::sort(cells.begin(), cells.end());
    std::vector<std::uint64_t> brick_keys;
    for (const auto& [brick, bit] : cells)
        if (!brick_keys.empty() && brick_keys.back() == brick)
            masks_.back() |= bit;
        else
            brick_keys.push_back(brick), masks_.push_back(bit);
    const std::uint64_t total = count[0] * count[1] * count[2];
    if (total <= bitmap_bricks_limit) {
        bits_.assign((total + 63) / 64, 0);
        for (const std::uint64_t brick : brick_keys) bits_[brick / 64] |= std::uint64_t{1} << (brick % 64);
        ranks_.resize(bits_.size());
        std::uint32_t before = 0; // at most 2^28 bricks
        for (std::size_t w = 0; w < bits_.size(); ++w) {
            ranks_[w] = before;
            before += static_cast<std::uint32_t>(std::popcount(bits_[w]));
        }
    } else {
        table_ = BrickTable(brick_keys);
    }
}

} // namespace lasmesh
