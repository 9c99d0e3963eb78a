// SPDX-License-Identifier: Apache-2.0
#include "mesh/tile_facing.hpp"

#include "mesh/mesh_edit.hpp"
#include "mesh/place_bits.hpp"

#include <numeric>

namespace lasmesh {

std::array<double, 2> centroid_in_cells(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    std::array<double, 2> c{};
    for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 2; ++a) c[a] += double(m.positions[t[k]][a]) / (3 * m.cell_size);
    return c;
}

bool centroid_within(const Mesh& m, const std::array<std::uint32_t, 3>& t, const std::array<std::int64_t, 4>& window,
                     double margin) {
    const std::array<double, 2> c = centroid_in_cells(m, t);
    return c[0] >= double(window[0]) - margin && c[0] < double(window[1]) + margin &&
           c[1] >= double(window[2]) - margin && c[1] < double(window[3]) + margin;
}

TileParts tile_parts(const Mesh& sheet, const std::array<std::int64_t, 4>& window, const OutsideSpace& outside) {
    // A plate's split moves a triangle's centroid by under half a cell: the triangles a tile may
    // keep lie within a cell of its window.
    Mesh near;
    near.positions = sheet.positions;
    near.cell_size = sheet.cell_size;
    std::vector<char> in_window;
    for (const auto& t : sheet.triangles) {
        if (!centroid_within(sheet, t, window, 1)) continue;
        near.triangles.push_back(t);
        in_window.push_back(centroid_within(sheet, t, window));
    }
    const std::vector<std::uint32_t> root = connected_parts(near);
    TileParts parts;
    parts.of_vertex.assign(sheet.positions.size(), TileParts::none);
    std::vector<std::uint32_t> numbered(root.size(), TileParts::none); // per root vertex: its part
    for (const auto& t : near.triangles)
        for (const std::uint32_t v : t) {
            std::uint32_t& part = numbered[root[v]];
            if (part == TileParts::none) {
                part = static_cast<std::uint32_t>(parts.votes.size());
                parts.votes.push_back(0);
            }
            parts.of_vertex[v] = part;
        }
    const std::vector<double> votes = outside_votes(near, outside, sheet.cell_size);
    for (std::size_t i = 0; i < near.triangles.size(); ++i)
        if (in_window[i]) parts.votes[parts.of_vertex[near.triangles[i][0]]] += votes[i];
    // A vertex another tile's triangles share lies within a cell and a triangle's reach (under two
    // cells) of both windows: within 3 cells of this one's edges.
    for (std::uint32_t v = 0; v < sheet.positions.size(); ++v) {
        if (parts.of_vertex[v] == TileParts::none) continue;
        const double x = double(sheet.positions[v][0]) / sheet.cell_size,
                     y = double(sheet.positions[v][1]) / sheet.cell_size;
        if (x > double(window[0]) + 3 && x < double(window[1]) - 3 && y > double(window[2]) + 3 &&
            y < double(window[3]) - 3)
            continue;
        parts.shared.push_back({sheet.positions[v], parts.of_vertex[v]});
    }
    return parts;
}

std::vector<std::vector<char>> outside_turns(const std::vector<TileParts>& tiles) {
    std::vector<std::size_t> first(tiles.size() + 1, 0); // each tile's first part, numbered over all tiles
    for (std::size_t k = 0; k < tiles.size(); ++k) first[k + 1] = first[k] + tiles[k].votes.size();
    std::vector<std::size_t> root(first.back());
    std::iota(root.begin(), root.end(), std::size_t{0});
    const auto find = [&](std::size_t a) {
        while (root[a] != a) a = root[a] = root[root[a]];
        return a;
    };
    PlaceMap<std::size_t> at;
    for (std::size_t k = 0; k < tiles.size(); ++k)
        for (const TileParts::Shared& s : tiles[k].shared) {
            const auto [it, fresh] = at.try_emplace(s.place, first[k] + s.part);
            if (fresh) continue;
            const std::size_t a = find(it->second), b = find(first[k] + s.part);
            if (a != b) root[std::max(a, b)] = std::min(a, b);
        }
    std::vector<double> votes(root.size(), 0);
    for (std::size_t k = 0; k < tiles.size(); ++k)
        for (std::size_t p = 0; p < tiles[k].votes.size(); ++p) votes[find(first[k] + p)] += tiles[k].votes[p];
    std::vector<std::vector<char>> turns(tiles.size());
    for (std::size_t k = 0; k < tiles.size(); ++k)
        for (std::size_t p = 0; p < tiles[k].votes.size(); ++p) turns[k].push_back(votes[find(first[k] + p)] < 0);
    return turns;
}

std::vector<char> vertex_turns(const TileParts& parts, const std::vector<char>& turns) {
    std::vector<char> turn(parts.of_vertex.size(), 0);
    for (std::size_t v = 0; v < turn.size(); ++v)
        if (parts.of_vertex[v] != TileParts::none) turn[v] = turns[parts.of_vertex[v]];
    return turn;
}

} // namespace lasmesh
