// Accumulation: every point of a LAS stream counted into a grid cell on the OpenCL device, with
// the sums of its colour words, in slices that fit the device's largest allocation.
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
    std::uint64_t max_alloc = 0;    // lower the device's maximum allocation (tests); 0: the device's
    // Called after each slice is read, with the points read so far (progress display).
    std::function<void(std::uint64_t points_read)> on_slice;
};

struct DensityGrid {
    GridSpec spec;
    std::vector<std::uint64_t> count; // points per cell, cell index as in GridSpec
    // Sums of the stored 16-bit colour words per cell; empty when the format has no colour.
    std::vector<std::uint64_t> red, green, blue;
    std::uint64_t points_read = 0;
    std::uint64_t points_outside = 0;
    std::uint32_t color_max_word = 0; // the largest R, G or B word in the file

    bool has_color() const { return !red.empty(); }
    // Colour words all <= 255 mean 8-bit values stored in 16-bit fields (the common case);
    // anything larger means true 16-bit colour, scaled by 255 / 65535.
    bool color_is_16bit() const { return color_max_word > 255; }
    // The average colour of a cell's points as 8-bit sRGB (rounded); black for an empty cell.
    Rgb8 mean_color(std::uint64_t cell) const;
};

// Bytes a grid and its slices take: on the device, and on the host for the read-back grid and
// the staging slices.
struct MemoryNeed {
    std::uint64_t device_bytes = 0;
    std::uint64_t host_bytes = 0;
    std::uint64_t largest_buffer = 0; // the grid buffer on the device
};
MemoryNeed memory_need(const GridSpec& grid, bool has_color, std::uint64_t slice_bytes);

// The grid for `header` under `options`: the requested cells over --bounds or the header bounds.
GridSpec grid_for(const LasHeader& header, const AccumulateOptions& options);

// Reads every remaining record of `reader` and accumulates it on `device`. Refuses, before
// allocating anything, a grid that does not fit the device's memory, its largest allocation or
// options.max_memory (Error, usage, naming the bytes needed and a --grid that fits). Reading the
// next slice overlaps the device's work on the current one.
DensityGrid accumulate_density(LasReader& reader, ComputeDevice& device, const AccumulateOptions& options);

} // namespace lasmesh
