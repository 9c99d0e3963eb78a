// SPDX-License-Identifier: Apache-2.0
#include "mesh/tiled_sheet.hpp"

#include "grid/thin_parts.hpp"
#include "mesh/mesh_edit.hpp"
#include "mesh/tile_facing.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <tuple>

namespace lasmesh {

namespace {

// `mesh` with its vertices of one place and one normal (bit for bit) made one, numbered as its
// triangles first use them: tiles meshed apart give the vertices they share the same bits. The
// normal counts: where two sheets meet, each keeps a vertex of its own at the same place (16,330
// of the 2M deck's 276,187), told apart by their normals (none share both); joined, the sheets
// would be glued together there. Numbered by sorting the vertices by their bits, not in a hash
// map: 12 bytes a vertex.
Mesh joined_by_place(Mesh&& mesh) {
    const std::size_t vertices = mesh.positions.size();
    std::vector<std::uint32_t> place(vertices);
    {
        const auto bits = [&](std::uint32_t v) {
            std::array<std::uint32_t, 6> key{};
            for (int a = 0; a < 3; ++a) {
                key[a] = std::bit_cast<std::uint32_t>(mesh.positions[v][a]);
                if (!mesh.normals.empty()) key[3 + a] = std::bit_cast<std::uint32_t>(mesh.normals[v][a]);
            }
            return key;
        };
        std::vector<std::uint32_t> by_place(vertices);
        for (std::uint32_t v = 0; v < vertices; ++v) by_place[v] = v;
        std::sort(by_place.begin(), by_place.end(), [&](std::uint32_t a, std::uint32_t b) {
            return std::make_pair(bits(a), a) < std::make_pair(bits(b), b);
        });
        for (std::size_t i = 0, n = 0; i < vertices; ++i) {
            n += i > 0 && bits(by_place[i]) != bits(by_place[i - 1]);
            place[by_place[i]] = static_cast<std::uint32_t>(n);
        }
    }
    Mesh joined;
    joined.origin = mesh.origin, joined.cell_size = mesh.cell_size, joined.crs = mesh.crs;
    joined.triangles = std::move(mesh.triangles);
    std::vector<std::uint32_t> index(vertices, ~std::uint32_t{0}); // per place: its vertex in `joined`
    for (std::array<std::uint32_t, 3>& t : joined.triangles)
        for (std::uint32_t& v : t) {
            std::uint32_t& at = index[place[v]];
            if (at == ~std::uint32_t{0}) {
                at = static_cast<std::uint32_t>(joined.positions.size());
                joined.positions.push_back(mesh.positions[v]);
                if (!mesh.colors.empty()) joined.colors.push_back(mesh.colors[v]);
                if (!mesh.normals.empty()) joined.normals.push_back(mesh.normals[v]);
            }
            v = at;
        }
    return joined;
}

} // namespace

std::vector<std::array<std::int64_t, 4>> tile_windows(const GridSpec& grid, std::int64_t tile_cells) {
    std::vector<std::array<std::int64_t, 4>> windows;
    for (std::int64_t y = 0; y < std::int64_t{grid.dims[1]}; y += tile_cells)
        for (std::int64_t x = 0; x < std::int64_t{grid.dims[0]}; x += tile_cells)
            windows.push_back({x, std::min(x + tile_cells, std::int64_t{grid.dims[0]}), y,
                               std::min(y + tile_cells, std::int64_t{grid.dims[1]})});
    return windows;
}

std::vector<std::array<std::int64_t, 3>> tile_thin_cells(const CellGrid& part, double iso,
                                                         const std::array<std::int64_t, 4>& window) {
    std::vector<std::array<std::int64_t, 3>> thin = thin_cells(part, iso);
    std::erase_if(thin, [&](const std::array<std::int64_t, 3>& c) {
        return c[0] < window[0] || c[0] >= window[1] || c[1] < window[2] || c[1] >= window[3];
    });
    return thin;
}

TiledSurvey survey_tiles(const GridSpec& grid, const std::vector<std::array<std::int64_t, 4>>& windows,
                         const TilePart& part_of, double iso, bool thin) {
    std::vector<SurveyPart> parts;
    TiledSurvey tiled;
    for (const auto& w : windows) {
        const CellGrid part = part_of(w);
        if (part.cells.empty()) continue;
        parts.push_back(sheet_survey_part(part, iso, w));
        if (!thin) continue;
        const std::vector<std::array<std::int64_t, 3>> cells = tile_thin_cells(part, iso, w);
        tiled.thin.insert(tiled.thin.end(), cells.begin(), cells.end());
    }
    std::sort(tiled.thin.begin(), tiled.thin.end(),
              [](const auto& a, const auto& b) { return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]); });
    tiled.survey = combined_survey(parts, grid.dims);
    return tiled;
}

PlaneFacing face_tiles(const GridSpec& grid, const std::vector<std::array<std::int64_t, 4>>& windows,
                       const TilePart& part_of, double iso, const SheetSurvey& survey) {
    std::vector<UnfacedPlanes> parts;
    for (const auto& w : windows)
        if (const CellGrid part = part_of(w); !part.cells.empty())
            parts.push_back(unfaced_planes(part, iso, survey, w));
    return plane_facing(std::move(parts), grid, survey);
}

TileSheet tile_sheet(const CellGrid& part, double iso, const SheetSurvey& survey, const PlaneFacing& facing,
                     const std::array<std::int64_t, 4>& window, SeamCorners* seam) {
    std::optional<SeamRequest> request;
    std::vector<std::size_t> near; // the indices in `seam` of the corners the tile samples
    if (seam) {
        SeamCorners mine;
        mine.dims = seam->dims;
        for (std::size_t i = 0; i < seam->corners.size(); ++i) {
            const std::array<std::int64_t, 3> c = seam->corner_of(seam->corners[i]);
            // The corners on the window's far sides too: a corner's flags look one corner on.
            if (c[0] < window[0] || c[0] > window[1] || c[1] < window[2] || c[1] > window[3]) continue;
            mine.corners.push_back(seam->corners[i]);
            near.push_back(i);
        }
        const auto owned = [&](std::int64_t at, std::int64_t lo, std::int64_t hi, std::int64_t cells) {
            return at >= lo && (at < hi || at == cells);
        };
        request = SeamRequest{std::move(mine), [&](SeamCorners&& sampled) {
                                  for (std::size_t j = 0; j < near.size(); ++j) {
                                      const std::array<std::int64_t, 3> c = sampled.corner_of(sampled.corners[j]);
                                      if (!owned(c[0], window[0], window[1], seam->dims[0]) ||
                                          !owned(c[1], window[2], window[3], seam->dims[1]))
                                          continue;
                                      seam->value[near[j]] = sampled.value[j];
                                      seam->normal[near[j]] = sampled.normal[j];
                                      seam->flags[near[j]] = sampled.flags[j];
                                  }
                              }};
    }
    TileSheet sheet{faced_sheet(part, iso, survey, facing, LinearParts::planes, request ? &*request : nullptr), {}};
    sheet.parts = tile_parts(sheet.faced.mesh, window, *survey.outside);
    return sheet;
}

Mesh finish_tile_sheet(TileSheet&& sheet, const std::vector<char>& turns, const std::array<std::int64_t, 4>& window) {
    Mesh mesh = std::move(sheet.faced.mesh);
    turn_over(mesh, vertex_turns(sheet.parts, turns));
    if (!sheet.faced.half.empty()) split_two_faces(mesh, sheet.faced.half);
    std::erase_if(mesh.triangles,
                  [&](const std::array<std::uint32_t, 3>& t) { return !centroid_within(mesh, t, window); });
    return mesh;
}

Mesh sheets_of_tiles(const GridSpec& grid, const std::vector<std::array<std::int64_t, 4>>& windows,
                     const TilePart& part_of, double iso, const SheetSurvey& survey, SeamCorners* seam) {
    if (seam) { // a corner no tile samples (none of its tile's cells occupied) is undefined
        seam->value.assign(seam->corners.size(), 0);
        seam->normal.assign(seam->corners.size(), {});
        seam->flags.assign(seam->corners.size(), 0);
    }
    const PlaneFacing facing = face_tiles(grid, windows, part_of, iso, survey);
    std::vector<TileSheet> tiles;
    std::vector<TileParts> parts;
    for (const auto& w : windows) {
        const CellGrid part = part_of(w);
        tiles.push_back(part.cells.empty() ? TileSheet{} : tile_sheet(part, iso, survey, facing, w, seam));
        parts.push_back(tiles.back().parts);
    }
    const std::vector<std::vector<char>> turns = outside_turns(parts);
    // The tiles' meshes one after the other, then joined where they meet.
    Mesh all;
    all.origin = grid.origin, all.cell_size = grid.cell_size;
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        Mesh m = finish_tile_sheet(std::move(tiles[k]), turns[k], windows[k]);
        if (m.triangles.empty()) continue; // a tile without cells has no colours either
        remove_unused_vertices(m);
        if (all.triangles.empty())
            all.positions = std::move(m.positions), all.colors = std::move(m.colors),
            all.normals = std::move(m.normals), all.triangles = std::move(m.triangles);
        else
            append_mesh(all, m);
    }
    return joined_by_place(std::move(all));
}

Mesh in_tile_order(Mesh&& sheet, const GridSpec& grid, std::int64_t tile_cells) {
    // A triangle's tile as centroid_within finds it: the division only guesses, the comparisons decide.
    const std::int64_t across = (std::int64_t{grid.dims[0]} + tile_cells - 1) / tile_cells;
    const std::int64_t along = (std::int64_t{grid.dims[1]} + tile_cells - 1) / tile_cells;
    const auto tile_of = [&](double c, std::int64_t count) {
        auto t = std::clamp(static_cast<std::int64_t>(std::floor(c / double(tile_cells))), std::int64_t{0}, count - 1);
        while (t > 0 && c < double(t * tile_cells)) --t;
        while (t + 1 < count && c >= double((t + 1) * tile_cells)) ++t;
        return static_cast<std::uint64_t>(t);
    };
    std::vector<std::uint64_t> order(sheet.triangles.size()); // tile << 32 | triangle: sorted, tile by tile in order
    for (std::size_t i = 0; i < order.size(); ++i) {
        const std::array<double, 2> c = centroid_in_cells(sheet, sheet.triangles[i]);
        order[i] = (tile_of(c[1], along) * std::uint64_t(across) + tile_of(c[0], across)) << 32 | i;
    }
    std::sort(order.begin(), order.end());
    std::vector<std::array<std::uint32_t, 3>> ordered(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) ordered[i] = sheet.triangles[order[i] & 0xffffffffu];
    sheet.triangles = std::move(ordered);
    return joined_by_place(std::move(sheet));
}

Mesh extract_sheet_in_tiles(const CellGrid& grid, double iso, std::int64_t tile_cells, std::int64_t halo) {
    const std::vector<std::array<std::int64_t, 4>> windows = tile_windows(grid.spec, tile_cells);
    const TilePart part_of = [&](const std::array<std::int64_t, 4>& w) {
        return bricks_within(grid, w[0] - halo, w[1] + halo, w[2] - halo, w[3] + halo);
    };
    const TiledSurvey first = survey_tiles(grid.spec, windows, part_of, iso, false);
    return sheets_of_tiles(grid.spec, windows, part_of, iso, first.survey);
}

} // namespace lasmesh
