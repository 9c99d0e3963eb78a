// SPDX-License-Identifier: Apache-2.0
// The main job: `lasmesh INPUT... -o OUT.ply -o OUT.drc -o OUT.glb`: read, accumulate, extract once,
// write each output, with a summary.
#pragma once

#include "grid_options.hpp"
#include "lasmesh/build_mesh.hpp"

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace lasmesh::cli {

struct MeshOptions {
    std::vector<std::string> inputs;
    std::string inputs_list;          // --inputs LIST: one path a line
    bool skip_bad_inputs = false;     // --skip-bad-inputs
    bool refine_thin = false;         // --refine-thin: whatever the density
    bool no_refine_thin = false;      // --no-refine-thin (neither: ThinRefinement::automatic)
    std::string crs;                  // --crs
    double tile = 0;                  // --tile SIZE: a tileset's finest tiles (0: 64 cells)
    std::vector<std::string> outputs; // the format of each follows its extension
    GridOptions grid;
    std::string iso = "auto";
    std::string surface = "sheet";
    std::string placement = "surface";
    std::string min_piece = "5%";
    std::string simplify = "0.5cell";
    bool no_normals = false;
    std::string glb_compression = "none";
    std::string glb_origin = "extras";
    bool ascii = false;
    DracoOptions draco;  // for .drc and .glb outputs
    int threads = 0;     // 0: all cores
    std::string report;  // --report FILE.json
    std::string preview; // --preview FILE.png
    bool quiet = false, verbose = false;
    bool progress = false; // draw a progress line (set when stderr is a terminal)
};

void add_mesh_options(CLI::App& app, MeshOptions& options);
// The options after the inputs': -o, the grid's (when `with_grid`), then --iso to --verbose.
void add_meshing_options(CLI::App& app, MeshOptions& options, bool with_grid);
// --refine-thin and --no-refine-thin; `reading` says how the command reads the points again.
void add_thin_parts_options(CLI::App& app, MeshOptions& options, const std::string& reading);
// The option text converted into the library's options, which the library checks (before
// reading); throws Error (usage) without an output when `need_output`.
BuildOptions build_options(const MeshOptions& options, bool need_output = true);
// Throws Error (usage) when --tile is given without a tileset output (the command line's).
void check_tile_option(const BuildOptions& options);
// The inputs named on the command line, then those of --inputs LIST.
std::vector<std::string> all_inputs(const MeshOptions& options);
// Calls `run` with `options` and an observer drawing progress, then prints the summary as the main
// job does (merge prints it too).
void run_with_summary(const MeshOptions& o, BuildOptions options,
                      const std::function<BuildResult(const BuildOptions&, BuildObserver&)>& run,
                      std::ostream& summary);
// Runs the pipeline; the summary goes to `summary` (stderr).
void run_mesh(const MeshOptions& options, std::ostream& summary);

} // namespace lasmesh::cli
