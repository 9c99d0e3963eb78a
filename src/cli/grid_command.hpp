// SPDX-License-Identifier: Apache-2.0
// `lasmesh grid` and `lasmesh devices`: the accumulation stage on its own, and the devices it
// can run on.
#pragma once

#include "grid_options.hpp"

#include <ostream>

namespace lasmesh::cli {

struct GridCommandOptions {
    std::string input;
    GridOptions grid;
    bool json = false;
};

void run_grid(const GridCommandOptions& options, std::ostream& out);
void run_devices(std::ostream& out);

} // namespace lasmesh::cli
