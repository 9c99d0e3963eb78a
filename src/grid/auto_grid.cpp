// SPDX-License-Identifier: Apache-2.0
// choose_grid: points per unit of surface area, then the cell edge h that puts k =
// auto_grid_points_per_cell(N) points into a surface cell: N h^2 / A = k, h = sqrt(k A / N).
#include "grid/auto_grid.hpp"
#include "number_text.hpp"

#include "lasmesh/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>

namespace lasmesh {

double auto_grid_points_per_cell(std::uint64_t point_count) {
    return std::clamp(static_cast<double>(point_count) / auto_grid_detail_cells, auto_grid_fewest_points_per_cell,
                      auto_grid_most_points_per_cell);
}

std::uint64_t auto_grid_min_median(double points_per_cell) {
    return std::max<std::uint64_t>(2, static_cast<std::uint64_t>(std::lround(points_per_cell / 3)));
}

GridChoice choose_grid(std::uint64_t point_count, const Bounds& bounds, const std::string& input_name) {
    if (point_count < auto_grid_min_points)
        throw_input_error(input_name,
                          "has " + std::to_string(point_count) + " points, too few to outline a surface (" +
                              std::to_string(auto_grid_min_points) +
                              " at least for a grid chosen from the data); give a coarse grid yourself, e.g. 8 cells",
                          "grid");
    std::array<double, 3> e{};
    for (int a = 0; a < 3; ++a) e[a] = std::max(0.0, bounds.max[a] - bounds.min[a]);
    std::sort(e.begin(), e.end(), std::greater<>());
    // The two largest faces: a flat scan is one face (the third extent is ~0), a building's or a
    // hull's is about two.
    double area = e[0] * e[1] + e[0] * e[2];
    if (!(area > 0)) area = e[0] * e[0]; // points on a line or one spot: any cell size
    const double per_cell = auto_grid_points_per_cell(point_count);
    const double cell = std::sqrt(per_cell * area / static_cast<double>(point_count));
    const double wanted = cell > 0 && e[0] > 0 ? e[0] / cell : auto_grid_min_cells;
    const auto cells = static_cast<std::uint32_t>(
        std::clamp(std::round(wanted), double(auto_grid_min_cells), double(auto_grid_max_cells)));
    GridChoice choice;
    choice.request.kind = GridRequest::Kind::longest_axis;
    choice.request.dims = {cells, 0, 0};
    choice.points_per_cell = per_cell;
    choice.min_median = auto_grid_min_median(per_cell);
    choice.reason = significant(point_count / area, 3) + " points per unit of area over about " + significant(area, 3) +
                    " square units, " + significant(per_cell, 2) + " a cell: " + std::to_string(cells) + " cells" +
                    (wanted < auto_grid_min_cells   ? " (the fewest allowed)"
                     : wanted > auto_grid_max_cells ? " (the most chosen from the data; ask for more cells if need be)"
                                                    : "");
    return choice;
}

} // namespace lasmesh
