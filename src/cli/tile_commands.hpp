// SPDX-License-Identifier: Apache-2.0
// The survey over many machines, in three commands (lasmesh/build_mesh.hpp):
//   lasmesh plan INPUT... [--tile SIZE] -o site.plan.json   headers only: the grid and its tiles
//   lasmesh tile site.plan.json --index K                    one tile's cells (an array job's task)
//   lasmesh merge site.plan.json -o site/tileset.json        the tiles' cells meshed, as one machine would
#pragma once

#include "mesh_command.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <ostream>
#include <string>

namespace lasmesh::cli {

struct PlanOptions {
    MeshOptions survey; // the inputs, --crs and the grid's options
    double tile = 0;    // 0: chosen from the data
    std::string output;
};

struct TileOptions {
    std::string plan;
    std::optional<std::size_t> index; // else SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX
    GridOptions device;               // --device, --chunk-mb, --max-memory
    int threads = 0;
    bool quiet = false;
};

struct MergeOptions {
    std::string plan;
    MeshOptions mesh; // the outputs and meshing options
    bool in_tiles = false;
};

CLI::App* add_plan_command(CLI::App& app, PlanOptions& options);
CLI::App* add_tile_command(CLI::App& app, TileOptions& options);
CLI::App* add_merge_command(CLI::App& app, MergeOptions& options);

void run_plan(const PlanOptions& options, std::ostream& out);
void run_tile(const TileOptions& options, std::ostream& log);
void run_merge(const MergeOptions& options, std::ostream& summary);

// The tile index from --index, else from the scheduler's environment: `slurm` is
// SLURM_ARRAY_TASK_ID's value, `kubernetes` JOB_COMPLETION_INDEX's (null: unset). Throws Error (usage).
std::size_t tile_index(const std::optional<std::size_t>& given, const char* slurm, const char* kubernetes);

} // namespace lasmesh::cli
