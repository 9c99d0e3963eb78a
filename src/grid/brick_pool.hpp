// SPDX-License-Identifier: Apache-2.0
// Internal: how the device's pool of bricks is laid out over several buffers ("chunks"), the
// host's side of brick_words() in kernels/accumulate.cl. Chunk c holds
// 2^first_bits << min(c, doublings) bricks: the chunks double until they reach the device's
// largest allocation, then stay at it. The pool grows by adding a chunk, never by copying, and
// can be larger than any one allocation.
#pragma once

#include <algorithm>
#include <cstdint>

namespace lasmesh {

struct PoolLayout {
    static constexpr unsigned max_chunks = 12; // the kernels take this many pool buffers
    unsigned first_bits = 10;
    unsigned doublings = 0;

    std::uint64_t chunk_bricks(unsigned c) const { return std::uint64_t{1} << (first_bits + std::min(c, doublings)); }
    // The slot of chunk c's first brick; chunk_start(n) is the capacity of n chunks.
    std::uint64_t chunk_start(unsigned c) const {
        if (c <= doublings + 1) return ((std::uint64_t{1} << c) - 1) << first_bits;
        return (((std::uint64_t{2} << doublings) - 1) << first_bits) + (c - doublings - 1) * chunk_bricks(doublings);
    }
};

// Chunks of at most `largest_chunk_bricks` (>= 1) bricks, starting at 1024 bricks or fewer.
inline PoolLayout pool_layout(std::uint64_t largest_chunk_bricks) {
    unsigned top = 0; // floor(log2(largest)), at most 30 so slots stay 32-bit in the kernel
    while (top < 30 && (std::uint64_t{2} << top) <= largest_chunk_bricks) ++top;
    PoolLayout layout;
    layout.first_bits = std::min(10u, top);
    layout.doublings = top - layout.first_bits;
    return layout;
}

} // namespace lasmesh
