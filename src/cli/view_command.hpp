// SPDX-License-Identifier: Apache-2.0
// `lasmesh view INPUT... [-o OUT...]`: accumulates the inputs once, then serves a page on
// 127.0.0.1 where the mesh is looked at, measured, meshed again with other options (from the
// accumulated grid, or by reading again for another grid) and saved to the outputs named here.
#pragma once

#include "mesh_command.hpp"
#include "view_server.hpp"

#include <CLI/CLI.hpp>

#include <ostream>

namespace lasmesh::cli {

struct ViewOptions {
    MeshOptions mesh; // the first mesh's options; -o names what Save may write
    ServeOptions serve;
};

CLI::App* add_view_command(CLI::App& app, ViewOptions& options);
void run_view(const ViewOptions& options, std::ostream& out, std::ostream& log);

} // namespace lasmesh::cli
