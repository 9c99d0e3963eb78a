// The grid and device options shared by every command that accumulates a grid, declared once.
#pragma once

#include "lasmesh/density_grid.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace lasmesh::cli {

struct GridOptions {
    std::string grid = "256";
    double voxel = 0;
    std::string bounds;
    std::string device = "auto";
    double chunk_mb = 0;
    double max_memory_mb = 0;
};

void add_grid_options(CLI::App& command, GridOptions& options);

// Checks and converts the options; throws Error (usage) quoting a bad value.
AccumulateOptions accumulate_options(const GridOptions& options);

} // namespace lasmesh::cli
