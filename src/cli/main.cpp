// SPDX-License-Identifier: Apache-2.0
// The `lasmesh` command: parses options with CLI11, runs one library entry point per
// subcommand, and maps errors to the documented exit codes. Nothing below main() exits, except
// the signal thread (signals.cpp).
#include "compare_command.hpp"
#include "grid_command.hpp"
#include "help_format.hpp"
#include "info_command.hpp"
#include "kernel_cache.hpp"
#include "lasmesh/error.hpp"
#include "man_page.hpp"
#include "mesh_command.hpp"
#include "option_parsing.hpp"
#include "progress.hpp"
#include "signals.hpp"
#include "tile_commands.hpp"
#include "view_command.hpp"

#include <CLI/CLI.hpp>

#include <fstream>
#include <iostream>
#include <new>

namespace {

constexpr int exit_internal_error = 5;

} // namespace

int main(int argc, char** argv) {
    lasmesh::cli::handle_signals(); // before any thread exists
    const lasmesh::cli::KernelCache kernel_cache;
    CLI::App app{"lasmesh: turns LAS point clouds into small coloured triangle meshes"};
    app.set_version_flag("--version", std::string("lasmesh ") + LASMESH_VERSION);
    app.formatter(std::make_shared<lasmesh::cli::HelpFormatter>()); // before the subcommands: they take it
    app.require_subcommand(0, 1);
    app.footer("Examples:\n"
               "  lasmesh deck.las -o deck.ply -o deck.drc          PLY to edit, Draco to share, one pass\n"
               "  curl -s https://example.org/deck.las | lasmesh - -o deck.glb\n"
               "  zstdcat scan.las.zst | lasmesh - -o scan.ply      gzip/bzip2/xz/zstd are also read directly\n"
               "  lasmesh scan.laz -o scan.ply                      LAZ (LASzip) is decoded directly, in parallel\n"
               "  lasmesh station*.laz -o site.glb                  many files of one survey, one mesh\n"
               "  lasmesh --inputs tiles.txt -o site.glb            thousands of files: one path a line\n"
               "  lasmesh deck.las -o deck.ply --grid 512           finer: 512 cells along the longest axis\n"
               "  lasmesh valve.las -o valve.ply --voxel 0.01       cells of 1 cm, for a small part\n"
               "  lasmesh deck.las -o deck.ply --iso 8              fill only cells with more than 8 points\n"
               "  lasmesh info --scan deck.las                      header facts, and the real bounds\n"
               "  lasmesh compare deck.ply deck.las --heatmap d.ply how far the mesh is from the points\n"
               "  lasmesh plan scans/*.laz -o site.plan.json        a survey over many machines: plan, tile, merge\n"
               "\n"
               "Exit codes: 0 success, 1 usage, 2 bad input, 3 OpenCL device, 4 output, 5 internal error.\n"
               "More: man lasmesh, and docs/guide.md.");

    lasmesh::cli::MeshOptions mesh;
    lasmesh::cli::add_mesh_options(app, mesh);

    lasmesh::cli::InfoOptions info;
    CLI::App* info_command = app.add_subcommand(
        "info", "Print the header facts of LAS or LAZ files; of several, also what they make as one survey; "
                "or the levels of a 3D Tiles tileset (.json)");
    info_command->footer("Examples:\n  lasmesh info deck.las\n  lasmesh info --scan --json deck.las\n"
                         "  xzcat deck.las.xz | lasmesh info -\n  lasmesh info station*.laz\n"
                         "  lasmesh info site/tileset.json");
    info_command
        ->add_option("INPUT", info.inputs,
                     "LAS or LAZ files, or - for standard input (gzip, bzip2, xz, zstd recognised); or one "
                     "tileset .json")
        ->type_name("FILE...")
        ->required();
    info_command->add_flag("--json", info.json, "One JSON object instead of text");
    info_command->add_flag("--scan", info.scan, "Read every record: count, bounds and colour range from the data");
    info_command->add_option("--chunk-points", info.chunk_points, "Records per read while scanning")
        ->type_name("N")
        ->capture_default_str()
        ->check(lasmesh::cli::whole_number(1, std::uint64_t{1} << 30));

    lasmesh::cli::GridCommandOptions grid;
    CLI::App* grid_command =
        app.add_subcommand("grid", "Sum the points into grid cells on the OpenCL device and report on it");
    grid_command->footer("Examples:\n  lasmesh grid deck.las --grid 512\n  lasmesh grid deck.las --voxel 0.05 --json");
    grid_command
        ->add_option("INPUT", grid.input, "LAS or LAZ file, or - for standard input (gzip, bzip2, xz, zstd recognised)")
        ->required();
    lasmesh::cli::add_grid_options(*grid_command, grid.grid);
    grid_command->add_flag("--json", grid.json, "One JSON object instead of text");

    lasmesh::cli::CompareCommandOptions compare;
    CLI::App* compare_command = lasmesh::cli::add_compare_command(app, compare);

    lasmesh::cli::ViewOptions view;
    CLI::App* view_command = lasmesh::cli::add_view_command(app, view);

    lasmesh::cli::PlanOptions plan;
    CLI::App* plan_command = lasmesh::cli::add_plan_command(app, plan);
    lasmesh::cli::TileOptions tile;
    CLI::App* tile_command = lasmesh::cli::add_tile_command(app, tile);
    lasmesh::cli::MergeOptions merge;
    CLI::App* merge_command = lasmesh::cli::add_merge_command(app, merge);

    CLI::App* devices_command = app.add_subcommand("devices", "List the OpenCL devices with their memory");
    devices_command->footer(
        "Examples:\n  lasmesh devices\n  lasmesh deck.las -o deck.glb --device 1      the second device listed\n"
        "  lasmesh deck.las -o deck.glb --device nvidia the first whose name contains \"nvidia\"");
    // The build writes the man page from these declarations (hidden: not for users).
    std::string man_path;
    app.add_option("--man-page", man_path)->group("");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e); // --help, --version
        // One line with our prefix, like every other error, rather than CLI11's two.
        std::cerr << "lasmesh: " << e.what() << " (see lasmesh --help)\n";
        return static_cast<int>(lasmesh::ErrorKind::usage);
    }

    if (!man_path.empty()) {
        std::ofstream(man_path) << lasmesh::cli::man_page(app, LASMESH_VERSION);
        return 0;
    }

    try {
        // Every command but info compiles the kernels (devices lists devices, whose platforms it
        // opens, but compiles nothing).
        if (!*info_command && !*devices_command && !*plan_command) {
            if (const std::string problem = kernel_cache.problem(); !problem.empty())
                throw lasmesh::Error(lasmesh::ErrorKind::output, problem);
        }
        if (*info_command) lasmesh::cli::run_info(info, std::cout, std::cerr);
        if (*grid_command) lasmesh::cli::run_grid(grid, std::cout);
        if (*compare_command) lasmesh::cli::run_compare(compare, std::cout, std::cerr);
        if (*devices_command) lasmesh::cli::run_devices(std::cout);
        if (*view_command) lasmesh::cli::run_view(view, std::cout, std::cerr);
        if (*plan_command) lasmesh::cli::run_plan(plan, std::cout);
        if (*tile_command) lasmesh::cli::run_tile(tile, std::cerr);
        if (*merge_command) {
            merge.mesh.progress = lasmesh::cli::stderr_is_terminal();
            lasmesh::cli::run_merge(merge, std::cerr);
        }
        if (app.get_subcommands().empty()) {
            if (mesh.inputs.empty() && mesh.inputs_list.empty()) {
                std::cerr << app.help();
                return static_cast<int>(lasmesh::ErrorKind::usage);
            }
            mesh.progress = lasmesh::cli::stderr_is_terminal();
            lasmesh::cli::run_mesh(mesh, std::cerr);
        }
        std::cout.flush();
        if (!std::cout)
            throw lasmesh::Error(lasmesh::ErrorKind::output,
                                 "cannot write to standard output (closed pipe or full disk?)");
        return 0;
    } catch (const lasmesh::Error& e) {
        std::cerr << "lasmesh: " << e.what() << lasmesh::cli::flag_hint(e) << '\n';
        return e.exit_code();
    } catch (const std::bad_alloc&) {
        std::cerr << "lasmesh: out of memory: the system refused more (a smaller --grid needs less; with --max-memory "
                     "a run is refused before it starts, with a --grid that fits)\n";
        return exit_internal_error;
    } catch (const std::exception& e) {
        std::cerr << "lasmesh: internal error: " << e.what() << '\n';
        return exit_internal_error;
    }
}
