// SPDX-License-Identifier: Apache-2.0
// finest_sheet_in_tiles: the finest sheet meshed tile by tile and its thin parts joined to it, as
// mesh_grid joins them to the whole grid's sheet (build_mesh.cpp): the tiles sample the seam's
// corners each in its window, so the fine sheet ends on the seam's faces where the tiles' does.
#include "build_steps.hpp"
#include "mesh/mesh_edit.hpp"

namespace lasmesh {

TiledFinest finest_sheet_in_tiles(const GridSpec& grid, const std::vector<std::array<std::int64_t, 4>>& windows,
                                  const TilePart& part_of, double iso, bool iso_auto, const SheetSurvey& survey,
                                  const Refinement* refined) {
    TiledFinest finest;
    if (!refined) {
        finest.mesh = sheets_of_tiles(grid, windows, part_of, iso, survey);
        return finest;
    }
    SeamCorners seam = seam_corners_of(refined->cells, {grid.dims[0], grid.dims[1], grid.dims[2]});
    finest.mesh = sheets_of_tiles(grid, windows, part_of, iso, survey, &seam);
    const Mesh thin = thin_parts_mesh(*refined, iso, iso_auto, grid, [&]() -> const SeamCorners& { return seam; });
    keep_triangles_in_blocks(finest.mesh, grid, 0, refined->cells, false);
    finest.seam = append_joined(finest.mesh, thin, grid, refined->cells);
    return finest;
}

} // namespace lasmesh
