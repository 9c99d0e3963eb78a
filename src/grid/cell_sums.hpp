// SPDX-License-Identifier: Apache-2.0
// Accumulation: every point of a LAS stream counted into a grid cell on the OpenCL device, with
// the sums of its colour words and of its position inside the cell, in slices that fit the
// device's largest allocation. The grid is sparse: only bricks of B^3 cells that received a
// point take memory, so memory follows the scanned surface, not the volume it spans.
#pragma once

#include "grid/axis_cells.hpp"
#include "grid/compute_device.hpp"
#include "lasmesh/grid.hpp"
#include "lasmesh/las_reader.hpp"

#include <array>
#include <bit>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace lasmesh {

class SurveyReader;
using Rgb8 = std::array<std::uint8_t, 3>;

struct AccumulateOptions {
    GridRequest grid;
    std::optional<Bounds> bounds; // default: the header bounds
    std::optional<GridSpec> spec; // this exact grid instead of `grid` over `bounds` (a lattice shared by runs)
    // With `spec`: its cells' starts in raw integers, given rather than worked out from it. A
    // window of a larger grid (a tile job's tile) takes that grid's own starts, so its points fall
    // in the cells they fall in there, and its brick index covers the window, not the survey.
    std::optional<std::array<AxisCells, 3>> axes;
    std::uint64_t slice_bytes = 0;   // upper limit on one upload; 0: 16 MiB
    std::uint64_t max_memory = 0;    // host and device together; 0: no limit of ours
    std::uint64_t memory_in_use = 0; // resident before accumulating, counted against max_memory
    std::uint64_t max_alloc = 0;     // lower the device's maximum allocation (tests); 0: the device's
    // Use a CPU device as a discrete GPU is used: buffers in the device's own memory, filled and
    // uploaded by the device, instead of host memory mapped (tests run a GPU's path on PoCL).
    bool device_memory = false;
    // Called after each slice is read, with the points read so far (progress display).
    std::function<void(std::uint64_t points_read)> on_slice;
};

// Exact integer sums over the points of one cell.
struct CellSums {
    std::uint64_t count = 0;
    // Sums of the points' raw LAS integers minus the cell's first raw value, per axis: the
    // points' mean position inside the cell, exactly and in any order.
    std::array<std::uint64_t, 3> position{};
    std::array<std::uint64_t, 3> color{}; // sums of the stored 16-bit R, G, B words
    // Sums of the products of those offsets: xx, yy, zz, xy, xz, yz (modulo 2^64: exact while a
    // cell's count times its widest axis squared stays under 2^64, CellGrid::moments_exact).
    std::array<std::uint64_t, 6> moments{};
};
// The two axes of each moment sum.
constexpr std::array<std::array<int, 2>, 6> moment_axes{{{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}}};

// Bricks by linear key (x fastest): an open-addressing hash table with linear probing, so that
// looking a brick up takes memory and set-up time that follow the occupied bricks, not the volume
// the grid spans (a dense index over a 4096 x 4096 x 1024 grid took a gigabyte and most of a
// run's time for 20,000 points).
class BrickTable {
  public:
    BrickTable() = default;
    // keys[i] (unique) finds i + 1.
    explicit BrickTable(const std::vector<std::uint64_t>& keys);
    // The value of `key`, or 0 when it is not in the table.
    std::uint32_t find(std::uint64_t key) const {
        if (keys_.empty()) return 0;
        const std::size_t mask = keys_.size() - 1;
        for (std::size_t at = slot(key);; at = (at + 1) & mask) {
            if (keys_[at] == key) return values_[at];
            if (keys_[at] == empty) return 0;
        }
    }
    std::uint64_t bytes() const { return keys_.size() * (sizeof(std::uint64_t) + sizeof(std::uint32_t)); }

  private:
    static constexpr std::uint64_t empty = ~std::uint64_t{0}; // no brick has this key
    std::size_t slot(std::uint64_t key) const {
        return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
    }
    int shift_ = 63;
    std::vector<std::uint64_t> keys_;
    std::vector<std::uint32_t> values_;
};

struct CellGrid {
    // Cells per brick edge: 4 measured best on the deck (docs/benchmarks.md, "Sparse grid").
    static constexpr int brick_bits = 2;
    static constexpr std::int64_t brick_size = 1 << brick_bits;
    static constexpr std::int64_t brick_cells = brick_size * brick_size * brick_size;
    static_assert(brick_cells <= 64, "a brick's occupied cells are the bits of one 64-bit mask");

    GridSpec spec;
    std::string grid_reason;       // how an automatic grid was chosen ("auto: ..."); empty otherwise
    std::array<AxisCells, 3> axes; // each axis's cell starts in raw LAS integers
    Vec3 scale{1, 1, 1}, offset{}; // the LAS header's, to turn raw sums into coordinates
    std::array<std::uint32_t, 3> bricks{};
    // Only the cells that hold a point are kept. brick_table finds each occupied brick's linear
    // index (x fastest) and gives 1 + its position b in brick_keys, the occupied bricks' linear
    // indices in ascending order. Occupied brick b has its cells' bits set in brick_masks[b] (bit
    // (z * B + y) * B + x for the cell at (x, y, z) inside it), and their records at
    // cells[brick_first[b]], one after the other in the order of the bits. The bricks' runs of
    // records lie in `cells` in no particular order (the device's): anything whose result depends
    // on the order visits the cells with for_each_cell, which goes by brick_keys.
    BrickTable brick_table; // made from brick_keys once they are complete (index_bricks)
    std::vector<std::uint64_t> brick_keys;
    std::vector<std::uint64_t> brick_masks;
    std::vector<std::uint64_t> brick_first;
    std::vector<CellSums> cells;
    bool color = false;   // the point format has colour, and some point's colour is not 0
    bool moments = false; // the cells' moments were summed (accumulated, not made by hand)
    std::uint64_t points_read = 0;
    std::uint64_t points_outside = 0;
    std::uint32_t color_max_word = 0; // the largest R, G or B word in the file

    bool has_color() const { return color; }
    // Colour words all <= 255 mean 8-bit values stored in 16-bit fields (the common case);
    // anything larger means true 16-bit colour, scaled by 255 / 65535.
    bool color_is_16bit() const { return color_max_word > 255; }

    // The cell (x, y, z), or nullptr when no point fell in it or it lies outside the grid.
    const CellSums* find(std::int64_t x, std::int64_t y, std::int64_t z) const {
        const std::uint64_t r = record_of(x, y, z);
        return r == no_record ? nullptr : &cells[r];
    }
    std::uint64_t count(std::int64_t x, std::int64_t y, std::int64_t z) const {
        const CellSums* c = find(x, y, z);
        return c ? c->count : 0;
    }
    // The index in `cells` of cell (x, y, z), or no_record when no point fell in it or it lies
    // outside the grid (from the brick table and masks alone: the cells themselves may be gone).
    static constexpr std::uint64_t no_record = ~std::uint64_t{0};
    std::uint64_t record_of(std::int64_t x, std::int64_t y, std::int64_t z) const {
        if (x < 0 || y < 0 || z < 0 || x >= std::int64_t{spec.dims[0]} || y >= std::int64_t{spec.dims[1]} ||
            z >= std::int64_t{spec.dims[2]})
            return no_record;
        const std::uint64_t brick =
            (std::uint64_t(z >> brick_bits) * bricks[1] + std::uint64_t(y >> brick_bits)) * bricks[0] +
            std::uint64_t(x >> brick_bits);
        const std::uint32_t at = brick_table.find(brick);
        if (at == 0) return no_record;
        const std::int64_t m = brick_size - 1;
        const unsigned bit = unsigned(((z & m) * brick_size + (y & m)) * brick_size + (x & m));
        const std::uint64_t mask = brick_masks[at - 1];
        if (!(mask >> bit & 1)) return no_record;
        return brick_first[at - 1] + static_cast<std::uint64_t>(std::popcount(mask & ((std::uint64_t{1} << bit) - 1)));
    }
    // A cell's place in for_each_cell's order, as one number: its brick's key times brick_cells
    // plus its bit. The same in a part of the grid (its bricks keep the grid's keys).
    std::uint64_t order_key(const std::array<std::int64_t, 3>& c) const {
        const std::uint64_t brick =
            (std::uint64_t(c[2] >> brick_bits) * bricks[1] + std::uint64_t(c[1] >> brick_bits)) * bricks[0] +
            std::uint64_t(c[0] >> brick_bits);
        const std::int64_t m = brick_size - 1;
        return brick * brick_cells + std::uint64_t(((c[2] & m) * brick_size + (c[1] & m)) * brick_size + (c[0] & m));
    }
    // The grid coordinates of cell `bit` of brick `key`.
    std::array<std::int64_t, 3> cell_in_brick(std::uint64_t key, unsigned bit) const {
        const std::uint64_t bx = key % bricks[0], by = key / bricks[0] % bricks[1], bz = key / bricks[0] / bricks[1];
        return {std::int64_t(bx * brick_size + bit % brick_size),
                std::int64_t(by * brick_size + bit / brick_size % brick_size),
                std::int64_t(bz * brick_size + bit / (brick_size * brick_size))};
    }
    // visit(cell coordinates, record index) for every cell that holds a point, bricks in
    // ascending order of position and cells in the order of their bits: the same order whatever
    // order the device met them in.
    template <class Visit>
    void for_each_cell(Visit visit) const {
        for (std::size_t b = 0; b < brick_keys.size(); ++b) {
            std::uint64_t record = brick_first[b];
            for (std::uint64_t mask = brick_masks[b]; mask != 0; mask &= mask - 1, ++record)
                visit(cell_in_brick(brick_keys[b], static_cast<unsigned>(std::countr_zero(mask))), record);
        }
    }
    // Appends the cells of `brick` that hold a point to `cells`, in the order of their bits, and
    // returns its mask (brick_masks' form); its first record is the size of `cells` before.
    std::uint64_t append_occupied(const std::array<CellSums, brick_cells>& brick);
    // Makes brick_table from brick_keys.
    void index_bricks() { brick_table = BrickTable(brick_keys); }
    std::uint64_t occupied_cells() const;
    std::uint64_t fullest_cell() const; // the most points in one cell (0 for an empty grid)
    std::uint64_t median_count() const; // the median points in a cell that holds any (0 for none)
    // Bytes the grid holds on the host: the brick table, the occupied bricks and their cells.
    std::uint64_t host_bytes() const;
    // The average colour of a cell's points as 8-bit sRGB (rounded); black for an empty cell.
    Rgb8 mean_color(const CellSums& cell) const;
    // The mean position of a cell's points, relative to spec.origin.
    Vec3 centroid(const std::array<std::int64_t, 3>& cell, const CellSums& sums) const;
    // Whether every cell's moments are there and are its exact sums (not wrapped modulo 2^64): the fullest
    // cell's count times the widest cell's span squared, in raw units, is under 2^64.
    bool moments_exact() const;
    // The scatter of a cell's points about their centroid, sum (p - c)(p - c)^T in the grid's units
    // (xx, yy, zz, xy, xz, yz): its points' spread, the count times their covariance.
    std::array<double, 6> scatter(const CellSums& sums) const;
};

// The bricks of `grid` that hold cells x0 <= x < x1 and y0 <= y < y1 (all of z), with their
// cells, in the grid's own frame and size: a part of it, such as a tile and a halo round it,
// that a sheet can be meshed from with the whole grid's survey (mesh/surface_sheet.hpp).
CellGrid bricks_within(const CellGrid& grid, std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1);
// A grid with `grid`'s geometry (spec, axes, raw frame, colour, moments) and no cells yet; bricks
// are appended in ascending key order (append_brick), then index_bricks.
CellGrid empty_like(const CellGrid& grid);
void append_brick(CellGrid& part, std::uint64_t key, std::uint64_t mask, const CellSums* cells);
// Whether brick `key` of a grid of `bricks` bricks an axis holds cells x0 <= x < x1, y0 <= y < y1.
bool brick_within(std::uint64_t key, const std::array<std::uint32_t, 3>& bricks, std::int64_t x0, std::int64_t x1,
                  std::int64_t y0, std::int64_t y1);

// Bytes the grid needs before the first point: the brick index on the device, and the slices. The pool of bricks grows
// with the surface and is checked as it grows.
struct MemoryNeed {
    std::uint64_t device_bytes = 0;
    std::uint64_t host_bytes = 0;
    std::uint64_t largest_buffer = 0; // the brick index
};
MemoryNeed memory_need(const GridSpec& grid, std::uint64_t slice_bytes);

// Bytes one brick of cells takes on the device.
std::uint64_t brick_device_bytes(bool has_color);

// The grid for `header` under `options`: options.spec, else the requested cells over the bounds
// or the header bounds.
GridSpec grid_for(const LasHeader& header, const AccumulateOptions& options);

// Reads every remaining record of `reader` and accumulates it on `device`. Refuses, before
// allocating anything, a brick index that does not fit; stops with an Error (usage) when the
// pool of bricks would outgrow the device's memory, its largest allocation or
// options.max_memory, saying how far it got and a grid that would fit. Reading the next slice
// overlaps the device's work on the current one.
CellGrid accumulate_cells(SurveyReader& reader, ComputeDevice& device, const AccumulateOptions& options);
// The same for one input.
CellGrid accumulate_cells(LasReader& reader, ComputeDevice& device, const AccumulateOptions& options);

} // namespace lasmesh
