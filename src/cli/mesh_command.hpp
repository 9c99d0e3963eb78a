// The main job: `lasmesh INPUT -o OUT.ply`: read, accumulate, extract, write, with a summary.
#pragma once

#include "grid_options.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace lasmesh::cli {

struct MeshOptions {
    std::string input;
    std::vector<std::string> outputs;
    GridOptions grid;
    std::string iso = "auto";
    std::string placement = "surface";
    std::string min_piece = "5%";
    bool ascii = false;
    int threads = 0; // 0: all cores
};

void add_mesh_options(CLI::App& app, MeshOptions& options);
// Runs the pipeline; the summary goes to `summary` (stderr).
void run_mesh(const MeshOptions& options, std::ostream& summary);

} // namespace lasmesh::cli
