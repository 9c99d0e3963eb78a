// SPDX-License-Identifier: Apache-2.0
// Grid and device options: one declaration, used by `lasmesh grid` and the meshing command.
#include "grid_options.hpp"

#include "option_parsing.hpp"

#include "lasmesh/error.hpp"
#include "read/las_scan.hpp"

#include <filesystem>

namespace lasmesh::cli {

void add_cell_options(CLI::App& command, GridOptions& o, bool with_scan_bounds) {
    command
        .add_option(
            "--grid", o.grid,
            "Cells along the longest axis (N), or NXxNYxNZ, or auto (from the points' density); cells are cubes; the "
            "finest the mesh uses (coarsened while most occupied cells hold a single point)")
        ->type_name("N|NXxNYxNZ|auto")
        ->capture_default_str();
    command
        .add_option("--voxel", o.voxel,
                    "Cell edge in the unit of the coordinate system (metres, feet), or the file's without one "
                    "(overrides --grid)")
        ->type_name("LENGTH")
        ->check(positive_number());
    CLI::Option* bounds =
        command
            .add_option("--bounds", o.bounds, "The box to cover instead of the header bounds; not with --scan-bounds")
            ->type_name("MINX,MINY,MINZ,MAXX,MAXY,MAXZ");
    if (with_scan_bounds)
        command
            .add_flag("--scan-bounds", o.scan_bounds,
                      "Read the file twice: first for the points' real bounds (header bounds can be wrong), "
                      "then to grid them; files only, not standard input; not with --bounds")
            ->excludes(bounds);
}

void add_device_options(CLI::App& command, GridOptions& o) {
    command
        .add_option("--device", o.device,
                    "OpenCL device: auto (a GPU if any), an index or part of a name (see `lasmesh devices`)")
        ->type_name("auto|INDEX|NAME")
        ->capture_default_str();
    command
        .add_option("--chunk-mb", o.chunk_mb,
                    "Largest slice of records uploaded at once, MiB (default 16, "
                    "always under the device's largest allocation)")
        ->type_name("MIB")
        ->check(positive_number());
    command
        .add_option("--max-memory", o.max_memory_mb,
                    "Refuse grids needing more than this, MiB, host and device together")
        ->type_name("MIB")
        ->check(positive_number());
}

void add_grid_options(CLI::App& command, GridOptions& o) {
    add_cell_options(command, o, true);
    add_device_options(command, o);
}

AccumulateOptions accumulate_options(const GridOptions& o) {
    AccumulateOptions a;
    // --voxel wins over --grid; --grid auto is the default request, which the library resolves.
    if (o.voxel)
        a.grid = voxel_request(*o.voxel);
    else if (o.grid != "auto")
        a.grid = parse_grid_request(o.grid);
    if (!o.bounds.empty()) a.bounds = parse_bounds(o.bounds);
    a.slice_bytes = static_cast<std::uint64_t>(o.chunk_mb * 1048576.0);
    a.max_memory = static_cast<std::uint64_t>(o.max_memory_mb * 1048576.0);
    return a;
}

std::string outside_advice(std::uint64_t points_outside, std::uint64_t points_read) {
    if (points_outside == 0) return "";
    return "warning: " + std::to_string(points_outside) + " of " + std::to_string(points_read) +
           " points lie outside the grid and were left out (header bounds too small?); "
           "--scan-bounds or --bounds covers them\n";
}

} // namespace lasmesh::cli
