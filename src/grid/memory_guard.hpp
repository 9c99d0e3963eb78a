// SPDX-License-Identifier: Apache-2.0
// Internal: the memory guard of accumulate_cells. What the grid needs is checked before
// reading (the brick index, the slices, the pool's first chunk) and each time the pool of bricks
// grows, against the device's memory and largest allocation and the memory limit; a refusal says
// what did not fit and a grid that would.
#pragma once

#include "grid/cell_sums.hpp"
#include "read/las_header.hpp"

#include <array>
#include <cstdint>
#include <string>

namespace lasmesh {

// Slice buffers on the device: one being read while the device works on the other.
constexpr std::size_t slice_buffers = 2;

std::string mib(std::uint64_t bytes);
std::string dims_text(const GridSpec& grid);
// 32-bit words a cell takes on the device (kernels/accumulate.cl): the position sums in three
// 21-bit lanes of a 64-bit word, the count, with colour blue, red and green, then the moments;
// with colour padded to 16 (one 64-byte cache line, kernels/accumulate.cl).
std::uint64_t cell_words(bool color);
// The first of a cell's six moment words: three 64-bit words of two 32-bit lanes, or two of three
// 21-bit lanes (and two words unused) for cells narrow enough.
std::uint64_t moment_word(bool color);
// A cell's sums: a listed carry names its sum as the cell's place in the pool times this, plus
// the sum (x, y, z, count, then blue, red, green with colour, then the six moments).
std::uint64_t cell_sums(bool color);
std::array<std::uint32_t, 3> brick_dims(const GridSpec& grid);
std::uint64_t brick_count(const GridSpec& grid);
// The pool's first chunk, counted before reading (bricks with colour, the larger kind).
std::uint64_t first_chunk_bytes(const GridSpec& grid);

struct MemoryLimits {
    std::uint64_t global_memory, max_alloc, max_memory, in_use;
};

// Empty when `need` fits; otherwise what it exceeds (`what` names the buffer for the largest
// allocation).
std::string exceeded(const MemoryNeed& need, const MemoryLimits& limits, const std::string& what);

// Refuses (Error, usage) a grid whose brick index and slices do not fit, naming the largest
// grid whose would.
void check_index_memory(const LasHeader& header, const AccumulateOptions& options, const GridSpec& grid,
                        std::uint64_t slice_bytes, const MemoryLimits& limits);

// The pool of bricks outgrew a limit after `points_read` of the header's points: stops with a
// grid whose pool would fit in `available_bytes`, costing `cost_per_brick_byte` per byte of
// bricks in use.
[[noreturn]] void pool_too_large(const LasHeader& header, const GridSpec& grid, const std::string& problem,
                                 std::uint64_t bricks_used, std::uint64_t points_read, std::uint64_t available_bytes,
                                 double cost_per_brick_byte);

} // namespace lasmesh
