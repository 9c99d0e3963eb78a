// SPDX-License-Identifier: Apache-2.0
// CellSet: a set of a grid's cells asked about once for every point read (the thin parts' second
// read keeps the points near them), so most answers must come from memory that stays in cache. A
// bit per 4 x 4 x 4 brick of the grid says whether the brick holds any of the cells (most points
// are turned away there), then the 64-bit mask of such a brick, found by the rank of its bit
// (Jacobson 1989, "Space-efficient static trees and graphs"), says which of its cells. On the
// 181M-point deck a hash of the cells behind the same bits took twice the time (its probes miss
// the caches), and a bit per 8 x 8 x 8 block with 512-bit masks a fifth more.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "grid/cell_sums.hpp"

namespace lasmesh {

class CellSet {
  public:
    // The bit per brick is kept for grids of at most this many bricks (32 MiB of bits); past
    // it the bricks that hold a cell are found in a hash.
    static constexpr std::uint64_t max_bitmap_bricks = std::uint64_t{1} << 28;

    CellSet() = default;
    // The cells whose keys ((z * dims[1] + y) * dims[0] + x) are `keys`, in a grid of `dims`
    // cells an axis.
    CellSet(const std::vector<std::uint64_t>& keys, const std::array<std::int64_t, 3>& dims,
            std::uint64_t bitmap_bricks_limit = max_bitmap_bricks);

    // Whether cell (x, y, z), inside the grid, is in the set.
    bool contains(std::uint64_t x, std::uint64_t y, std::uint64_t z) const {
        constexpr int b = CellGrid::brick_bits;
        const std::uint64_t brick = ((z >> b) * bricks_[1] + (y >> b)) * bricks_[0] + (x >> b);
        std::uint64_t at = 0;
        if (!bits_.empty()) {
            const std::uint64_t word = bits_[brick / 64], bit = std::uint64_t{1} << (brick % 64);
            if (!(word & bit)) return false;
            at = ranks_[brick / 64] + static_cast<std::uint64_t>(std::popcount(word & (bit - 1)));
        } else {
            const std::uint32_t found = table_.find(brick);
            if (found == 0) return false;
            at = found - 1;
        }
        constexpr std::uint64_t m = CellGrid::brick_size - 1;
        return masks_[at] >> (((((z & m) << b) + (y & m)) << b) + (x & m)) & 1;
    }
    // Whether the bricks are found by the bit per brick (else by the hash).
    bool has_bitmap() const { return !bits_.empty(); }

  private:
    static_assert(CellGrid::brick_cells == 64, "a brick's cells are the bits of one 64-bit mask");
    std::array<std::uint64_t, 2> bricks_{}; // bricks along x and y
    std::vector<std::uint64_t> bits_;       // a bit per brick of the grid, x fastest
    std::vector<std::uint32_t> ranks_;      // the set bits before each word of bits_
    BrickTable table_;                      // or the bricks' keys, when bits_ would be too large
    std::vector<std::uint64_t> masks_;      // the cells of each brick that holds any, in key order
};

} // namespace lasmesh
