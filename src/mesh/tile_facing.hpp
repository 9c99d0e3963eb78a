// SPDX-License-Identifier: Apache-2.0
// Tiles' sheets turned to face the outside as the whole grid's sheet is.
//
//     std::vector<TileParts> parts;
//     for (k...) parts.push_back(tile_parts(faced[k].mesh, windows[k], *survey.outside));
//     const std::vector<std::vector<char>> turns = outside_turns(parts);
//     for (k...) turn_over(faced[k].mesh, vertex_turns(parts[k], turns[k]));
//
// The sheet's last look at the whole is step 5 (surface_sheet.hpp): each connected part of the
// mesh turns when more of its area has the outside behind it than in front. Tiles' sheets faced
// alike (plane_facing) are the whole grid's sheet before that step, each tile's from its
// triangles whose centroid lies in its window; a connected part may run through many tiles. What
// decides its turn is small beside the meshes: each tile's parts, their triangles' votes (in the
// window: each triangle counted by one tile), and the places of the vertices near the window's
// edges, where a part may go on in the next tile. The parts are joined where two tiles have a
// vertex at the same place (a halo of 8 cells or more gives the tiles the whole grid's triangles
// there, bit for bit) and each joined part's votes added up.
#pragma once

#include "lasmesh/mesh.hpp"
#include "mesh/outside_space.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace lasmesh {

// Triangle t's centroid in x and y, in cells of m.cell_size from the grid origin: the one sum
// that says which tile a triangle belongs to (centroid_within; in_tile_order), the same to the bit.
std::array<double, 2> centroid_in_cells(const Mesh& m, const std::array<std::uint32_t, 3>& t);

// Whether triangle t's centroid lies in `window` (x from window[0] to window[1], y from window[2]
// to window[3], in cells of m.cell_size, from the grid origin), or within `margin` cells of it:
// the tile a triangle belongs to.
bool centroid_within(const Mesh& m, const std::array<std::uint32_t, 3>& t, const std::array<std::int64_t, 4>& window,
                     double margin = 0);

// What outside_turns needs of one tile's sheet.
struct TileParts {
    static constexpr std::uint32_t none = UINT32_MAX;
    // Per vertex: its part, among the triangles whose centroid lies within a cell of the window
    // (those a tile may keep once plates are split); none for the others.
    std::vector<std::uint32_t> of_vertex;
    std::vector<double> votes; // per part: outside_votes of its triangles in the window
    struct Shared {
        std::array<float, 3> place;
        std::uint32_t part = 0;
    };
    std::vector<Shared> shared; // the parts' vertices within 3 cells of the window's edges
};

// `sheet`'s positions are relative to the grid origin, in cells of `cell` (its cell_size).
TileParts tile_parts(const Mesh& sheet, const std::array<std::int64_t, 4>& window, const OutsideSpace& outside);

// Per tile, per part: whether it turns (1) or not (0): the tiles' parts joined where they share a
// vertex, a joined part turning where its votes add up below 0, as step 5 turns the whole grid's.
std::vector<std::vector<char>> outside_turns(const std::vector<TileParts>& tiles);

// Per vertex of the tile's sheet, for turn_over: its part's turn (0 for a vertex in none).
std::vector<char> vertex_turns(const TileParts& parts, const std::vector<char>& turns);

} // namespace lasmesh
