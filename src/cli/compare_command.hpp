// SPDX-License-Identifier: Apache-2.0
// `lasmesh compare MESH INPUT`: how far the mesh is from the cloud, both ways.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <ostream>
#include <string>

namespace lasmesh::cli {

struct CompareCommandOptions {
    std::string mesh, input, heatmap;
    std::uint64_t samples = 5'000'000, mesh_samples = 1'000'000;
    double cell_size = 0, heatmap_scale = 0;
    bool json = false;
};

CLI::App* add_compare_command(CLI::App& app, CompareCommandOptions& options);
// The report goes to `out`; the heat map legend, when one is written, to `log`.
void run_compare(const CompareCommandOptions& options, std::ostream& out, std::ostream& log);

} // namespace lasmesh::cli
