// Accumulation: every point of a LAS stream counted into a grid cell on the OpenCL device, with
// the sums of its colour words and of its position inside the cell, in slices that fit the
// device's largest allocation. The grid is sparse: only bricks of B^3 cells that received a
// point take memory, so memory follows the scanned surface, not the volume it spans.
#pragma once

#include "lasmesh/grid/compute_device.hpp"
#include "lasmesh/grid/grid.hpp"
#include "lasmesh/read/las_reader.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace lasmesh {

using Rgb8 = std::array<std::uint8_t, 3>;

struct AccumulateOptions {
    GridRequest grid;
    std::optional<Bounds> bounds;   // default: the header bounds
    std::uint64_t slice_bytes = 0;  // upper limit on one upload (--chunk-mb); 0: 16 MiB
    std::uint64_t max_memory = 0;   // --max-memory, host and device together; 0: no limit of ours
    std::uint64_t memory_in_use = 0; // resident before accumulating, counted against max_memory
    std::uint64_t max_alloc = 0;    // lower the device's maximum allocation (tests); 0: the device's
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
};

struct DensityGrid {
    // Cells per brick edge: 4 measured best on the deck (docs/benchmarks.md, "Sparse grid").
    static constexpr int brick_bits = 2;
    static constexpr std::int64_t brick_size = 1 << brick_bits;
    static constexpr std::int64_t brick_cells = brick_size * brick_size * brick_size;

    GridSpec spec;
    std::array<AxisCells, 3> axes; // each axis's cell starts in raw LAS integers
    Vec3 scale{1, 1, 1}, offset{}; // the LAS header's, to turn raw sums into coordinates
    std::array<std::uint32_t, 3> bricks{};
    // Per brick (x fastest): 0 when none of its cells holds a point, else 1 + its position in
    // brick_keys. brick_keys lists the occupied bricks' linear indices in ascending order, and
    // `cells` holds brick_cells records for each, in the same order (x fastest inside a brick):
    // the layout does not depend on the order in which the device met the bricks.
    std::vector<std::uint32_t> brick_index;
    std::vector<std::uint64_t> brick_keys;
    std::vector<CellSums> cells;
    bool color = false;
    std::uint64_t points_read = 0;
    std::uint64_t points_outside = 0;
    std::uint32_t color_max_word = 0; // the largest R, G or B word in the file

    bool has_color() const { return color; }
    // Colour words all <= 255 mean 8-bit values stored in 16-bit fields (the common case);
    // anything larger means true 16-bit colour, scaled by 255 / 65535.
    bool color_is_16bit() const { return color_max_word > 255; }

    // The cell (x, y, z), or nullptr when it lies outside the grid or in a brick with no points.
    const CellSums* find(std::int64_t x, std::int64_t y, std::int64_t z) const {
        const std::uint64_t r = record_of(x, y, z);
        return r == no_record ? nullptr : &cells[r];
    }
    std::uint64_t count(std::int64_t x, std::int64_t y, std::int64_t z) const {
        const CellSums* c = find(x, y, z);
        return c ? c->count : 0;
    }
    // The index in `cells` of cell (x, y, z), or no_record when it lies outside the grid or in a
    // brick with no points (from the brick index alone).
    static constexpr std::uint64_t no_record = ~std::uint64_t{0};
    std::uint64_t record_of(std::int64_t x, std::int64_t y, std::int64_t z) const {
        if (x < 0 || y < 0 || z < 0 || x >= std::int64_t{spec.dims[0]} || y >= std::int64_t{spec.dims[1]} ||
            z >= std::int64_t{spec.dims[2]})
            return no_record;
        const std::uint64_t brick =
            (std::uint64_t(z >> brick_bits) * bricks[1] + std::uint64_t(y >> brick_bits)) * bricks[0] + std::uint64_t(x >> brick_bits);
        const std::uint32_t at = brick_index[brick];
        if (at == 0) return no_record;
        const std::int64_t m = brick_size - 1;
        return (at - 1) * std::uint64_t{brick_cells} + std::uint64_t(((z & m) * brick_size + (y & m)) * brick_size + (x & m));
    }
    // The grid coordinates of record `n` of `cells`.
    std::array<std::int64_t, 3> cell_of_record(std::uint64_t n) const {
        const std::uint64_t key = brick_keys[n / brick_cells], local = n % brick_cells;
        const std::uint64_t bx = key % bricks[0], by = key / bricks[0] % bricks[1], bz = key / bricks[0] / bricks[1];
        return {std::int64_t(bx * brick_size + local % brick_size), std::int64_t(by * brick_size + local / brick_size % brick_size),
                std::int64_t(bz * brick_size + local / (brick_size * brick_size))};
    }
    std::uint64_t occupied_cells() const;
    // The average colour of a cell's points as 8-bit sRGB (rounded); black for an empty cell.
    Rgb8 mean_color(const CellSums& cell) const;
    // The mean position of a cell's points, relative to spec.origin.
    Vec3 centroid(const std::array<std::int64_t, 3>& cell, const CellSums& sums) const;
};

// Bytes the grid needs before the first point: the brick index on the device and the host, and
// the slices. The pool of bricks grows with the surface and is checked as it grows.
struct MemoryNeed {
    std::uint64_t device_bytes = 0;
    std::uint64_t host_bytes = 0;
    std::uint64_t largest_buffer = 0; // the brick index
};
MemoryNeed memory_need(const GridSpec& grid, std::uint64_t slice_bytes);

// Bytes one brick of cells takes on the device.
std::uint64_t brick_device_bytes(bool has_color);

// The grid for `header` under `options`: the requested cells over --bounds or the header bounds.
GridSpec grid_for(const LasHeader& header, const AccumulateOptions& options);

// Reads every remaining record of `reader` and accumulates it on `device`. Refuses, before
// allocating anything, a brick index that does not fit; stops with an Error (usage) when the
// pool of bricks would outgrow the device's memory, its largest allocation or
// options.max_memory, saying how far it got and a --grid that would fit. Reading the next slice
// overlaps the device's work on the current one.
DensityGrid accumulate_density(LasReader& reader, ComputeDevice& device, const AccumulateOptions& options);

} // namespace lasmesh
