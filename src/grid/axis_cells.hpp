// SPDX-License-Identifier: Apache-2.0
// The exact rule that assigns a point to a cell, decided once in raw LAS integers so that every
// device, and the host, agree on it.
#pragma once

#include "lasmesh/grid.hpp"

#include <cstdint>
#include <vector>

namespace lasmesh {

// The cells of one axis in raw LAS integers: a raw value r lies in cell i when
// starts[i] <= r < starts[i + 1], and outside the grid when r < starts[0] or r >= starts[n].
// Worked out with the same double arithmetic as PointDecoder::to_world, so the host's idea of
// where a decoded point lies and the device's integer comparison never disagree.
struct AxisCells {
    std::vector<std::int64_t> starts; // n + 1 entries

    std::uint32_t count() const { return static_cast<std::uint32_t>(starts.size() - 1); }
    // The cell of raw value r, or -1 outside the grid (binary search: the reference rule).
    std::int64_t cell_of(std::int64_t raw) const;
};

AxisCells axis_cells(const GridSpec& grid, int axis, double scale, double offset);

} // namespace lasmesh
