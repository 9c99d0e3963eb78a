// SPDX-License-Identifier: Apache-2.0
// `lasmesh grid`: accumulate and report the grid (cells, occupancy, points outside, colour depth).
#include "grid_command.hpp"

#include "io/json.hpp"
#include "number_text.hpp"
#include "read/input_stream.hpp"
#include "read/las_scan.hpp"

#include <algorithm>
#include <chrono>
#include <iomanip>

namespace lasmesh::cli {

void run_devices(std::ostream& out) {
    for (const DeviceInfo& d : list_devices())
        out << d.index << "  " << d.type << "  " << d.name << "  [" << d.platform << ", " << d.version << "]  memory "
            << d.global_memory / 1048576 << " MiB, largest allocation " << d.max_alloc / 1048576 << " MiB\n";
}

void run_grid(const GridCommandOptions& options, std::ostream& out) {
    AccumulateOptions accumulate = accumulate_options(options.grid);
    if (options.grid.scan_bounds) {
        const ScanResult scan = scan_file(options.input);
        accumulate.bounds = Bounds{scan.min, scan.max};
    }
    LasReader reader(options.input);
    if (!accumulate.bounds) check_header_bounds_usable(reader.header(), reader.stream().name());
    ComputeDevice device(options.grid.device);
    const auto start = std::chrono::steady_clock::now();
    CellGrid grid = accumulate_cells(reader, device, accumulate);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const std::uint64_t occupied = grid.occupied_cells(), fullest = grid.fullest_cell();
    const std::uint64_t pool_bytes = grid.brick_keys.size() * brick_device_bytes(grid.has_color());
    const double outside_share = grid.points_read ? double(grid.points_outside) / grid.points_read : 0.0;
    const char* depth = !grid.has_color() ? "none" : grid.color_is_16bit() ? "16-bit" : "8-bit in 16-bit fields";
    if (options.json) {
        Json json;
        json["device"] = device.info().name;
        json["dims"] = grid.spec.dims;
        json["cell_size"] = grid.spec.cell_size;
        json["origin"] = grid.spec.origin;
        json["points_read"] = grid.points_read;
        json["points_outside"] = grid.points_outside;
        json["occupied_cells"] = occupied;
        json["max_points_per_cell"] = fullest;
        json["occupied_bricks"] = grid.brick_keys.size();
        json["brick_cells"] = CellGrid::brick_cells;
        json["pool_bytes"] = pool_bytes;
        json["host_grid_bytes"] = grid.host_bytes();
        json["color"] = depth;
        json["seconds"] = seconds;
        out << json_line(json) << '\n';
        return;
    }
    out << "device               " << device.info().name << " (" << device.info().type << ")\n"
        << "grid                 " << grid.spec.dims[0] << " x " << grid.spec.dims[1] << " x " << grid.spec.dims[2]
        << " cells of " << four_digits(grid.spec.cell_size)
        << (grid.grid_reason.empty() ? "" : " (" + grid.grid_reason + ")") << "\n"
        << "origin               " << coordinate(grid.spec.origin[0], grid.spec.cell_size / 1000) << " "
        << coordinate(grid.spec.origin[1], grid.spec.cell_size / 1000) << " "
        << coordinate(grid.spec.origin[2], grid.spec.cell_size / 1000) << "\n"
        << "points read          " << grid.points_read << "\n"
        << "points outside grid  " << grid.points_outside << " (" << std::fixed << std::setprecision(3)
        << 100 * outside_share << "%)\n"
        << "occupied cells       " << occupied << " of " << grid.spec.cell_count() << "\n"
        << "occupied bricks      " << grid.brick_keys.size() << " of " << CellGrid::brick_cells
        << " cells: " << std::setprecision(1) << pool_bytes / 1e6 << " MB of grid on the device, "
        << grid.host_bytes() / 1e6 << " MB on the host (occupied cells only)\n"
        << "most points in cell  " << fullest << "\n"
        << "colour               " << depth << "\n"
        << "read + accumulate    " << std::setprecision(3) << seconds << " s\n";
}

} // namespace lasmesh::cli
