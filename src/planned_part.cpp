// SPDX-License-Identifier: Apache-2.0
// planned_part: a window of a plan's grid and a halo round it, read from the files of the tiles
// that hold them, as a part of the grid (mesh/tiled_sheet.hpp's TilePart): the merge's way to
// mesh the grid tile by tile without holding it whole.
#include "build_steps.hpp"
#include "grid/tile_cells.hpp"
#include "lasmesh/error.hpp"

#include <algorithm>
#include <tuple>

namespace lasmesh {

CellGrid planned_part(const TilePlan& plan, const std::array<std::int64_t, 4>& window, std::int64_t halo,
                      const CellGrid& frame) {
    const std::int64_t x0 = window[0] - halo, x1 = window[1] + halo, y0 = window[2] - halo, y1 = window[3] + halo;
    CellGrid part = empty_like(frame);
    // Each brick of the part from the one tile that holds it (the tiles hold disjoint bricks),
    // in ascending key order as a grid keeps them.
    std::vector<TileCells> tiles;
    std::vector<std::tuple<std::uint64_t, std::size_t, std::size_t>> bricks; // key, tile, brick
    for (std::size_t k = 0; k < plan.tiles.size(); ++k) {
        const PlannedTile& t = plan.tiles[k];
        if (t.x_cells[1] <= x0 || t.x_cells[0] >= x1 || t.y_cells[1] <= y0 || t.y_cells[0] >= y1) continue;
        // Only the bricks of the part: of a neighbour's file, the few along the shared border.
        tiles.push_back(read_tile_bricks(
            tile_path(plan, k), [&](std::uint64_t key) { return brick_within(key, frame.bricks, x0, x1, y0, y1); }));
        if (tiles.back().plan_hash != plan.hash || tiles.back().index != k)
            throw_input_error(tile_path(plan, k), "from another plan, or another tile: run the tile again");
        const TileCells& cells = tiles.back();
        for (std::size_t i = 0; i < cells.brick_keys.size(); ++i)
            bricks.emplace_back(cells.brick_keys[i], tiles.size() - 1, i);
    }
    std::sort(bricks.begin(), bricks.end());
    for (const auto& [key, t, i] : bricks)
        append_brick(part, key, tiles[t].brick_masks[i], tiles[t].cells.data() + tiles[t].brick_first[i]);
    part.index_bricks();
    return part;
}

} // namespace lasmesh
