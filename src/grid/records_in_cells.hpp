// SPDX-License-Identifier: Apache-2.0
// RecordsInCells: keeps, of a slice of raw LAS records, those whose grid cell is in a CellSet,
// moved to the front in their order. The thin parts' second read keeps so the points near them:
// every record of the input passes it, most are turned away, so it must cost a few nanoseconds.
//
//     const CellSet cells(keys, dims);                       // must outlive `near`, as must grid
//     const RecordsInCells near(grid.axes, cells, record_length);
//     const std::size_t kept = near.keep(records, count); // records[0..kept) are the kept ones
#pragma once

#include "grid/axis_cells.hpp"
#include "grid/cell_set.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace lasmesh {

class RecordsInCells {
  public:
    // Cells by `axes` (the survey's frame: X, Y and Z the first three 32-bit words of a record
    // `record_length` bytes long); the set and the axes' starts are referred to, not copied.
    RecordsInCells(const std::array<AxisCells, 3>& axes, const CellSet& cells, std::size_t record_length);

    // Moves the records among records[0..count) whose cell is in the set to the front, in their
    // order, and returns how many they are. In parallel, blocks of records at a time.
    std::size_t keep(std::byte* records, std::size_t count) const;

  private:
    // One axis: the cell of each run of 2^shift raw values from the first start (that of the
    // run's first value); a run holds at most one cell's start, or a few where the cells are
    // narrower than the runs, which the starts then settle. Plain values, which the compiler
    // keeps in registers through the loop.
    struct Axis {
        std::int64_t first = 0;
        std::uint64_t span = 0; // raw values from the first start to the last
        int shift = 0;
        const std::uint16_t* cell_of_run = nullptr; // in runs_
        const std::int64_t* starts = nullptr;
    };
    // The cell of `record` along each axis; false outside the grid.
    static bool cell_of(const std::byte* record, const std::array<Axis, 3>& axes, std::array<std::uint64_t, 3>& cell);

    static_assert(max_grid_cells <= 65535, "a run's cell is kept in 16 bits");
    std::array<std::vector<std::uint16_t>, 3> runs_;
    std::array<Axis, 3> axes_;
    const CellSet* cells_;
    std::size_t length_;
};

} // namespace lasmesh
