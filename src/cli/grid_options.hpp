// SPDX-License-Identifier: Apache-2.0
// The grid and device options shared by every command that accumulates a grid, declared once.
#pragma once

#include "grid/cell_sums.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace lasmesh::cli {

struct GridOptions {
    std::string grid = "auto";   // as the library's default GridRequest
    std::optional<double> voxel; // given: checked, even when 0 or negative
    std::string bounds;
    bool scan_bounds = false;
    std::string device = "auto";
    double chunk_mb = 0;
    double max_memory_mb = 0;
};

void add_grid_options(CLI::App& command, GridOptions& options);
// Its two halves: the cells (--grid, --voxel, --bounds, and --scan-bounds when asked for), and the
// device (--device, --chunk-mb, --max-memory).
void add_cell_options(CLI::App& command, GridOptions& options, bool with_scan_bounds);
void add_device_options(CLI::App& command, GridOptions& options);

// Checks and converts the options; throws Error (usage) quoting a bad value. --grid auto is the
// default GridRequest, which accumulate_cells resolves from the data.
AccumulateOptions accumulate_options(const GridOptions& options);

// A line advising --scan-bounds or --bounds when points fell outside the grid; empty otherwise.
std::string outside_advice(std::uint64_t points_outside, std::uint64_t points_read);

} // namespace lasmesh::cli
