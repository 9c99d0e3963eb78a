// SPDX-License-Identifier: Apache-2.0
// Tiles' sheets turned to face the outside as one (src/mesh/tile_facing): a tile's parts, their
// votes counted in its window only and their vertices near its edges handed on; parts joined
// across tiles where they share a vertex, each joined part turning by the sum of its votes.
#include "mesh/tile_facing.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

using namespace lasmesh;

namespace {

// Tiles' parts made up: `votes` per tile and part, no shared vertices yet.
std::vector<TileParts> made_up(const std::vector<std::vector<double>>& votes) {
    std::vector<TileParts> tiles(votes.size());
    for (std::size_t k = 0; k < votes.size(); ++k) tiles[k].votes = votes[k];
    return tiles;
}

void share(std::vector<TileParts>& tiles, std::size_t tile, std::uint32_t part, std::array<float, 3> place) {
    tiles[tile].shared.push_back({place, part});
}

// A strip of unit squares facing up (+z), two triangles a square, x from x0 to x1 and y from y0
// to y0 + 2, at height z, positions in cells of 1; its vertices numbered x by x, y fastest.
void add_strip(Mesh& m, int x0, int x1, int y0, float z) {
    const auto first = static_cast<std::uint32_t>(m.positions.size());
    for (int x = x0; x <= x1; ++x)
        for (int y = y0; y <= y0 + 2; ++y) m.positions.push_back({float(x), float(y), z});
    const auto at = [&](int x, int y) { return first + std::uint32_t((x - x0) * 3 + (y - y0)); };
    for (int x = x0; x < x1; ++x)
        for (int y = y0; y < y0 + 2; ++y) {
            m.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
            m.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
        }
}

} // namespace

TEST_CASE("parts that share a vertex across tiles turn together, by their votes added up") {
    // Tile 0: parts voting +1 and -0.5; tile 1: -3 and +2; tile 2: +0.25.
    std::vector<TileParts> tiles = made_up({{1, -0.5}, {-3, 2}, {0.25}});
    SUBCASE("apart, each by its own votes") {
        CHECK(outside_turns(tiles) == std::vector<std::vector<char>>{{0, 1}, {1, 0}, {0}});
    }
    SUBCASE("joined in a chain across three tiles") {
        // 0:0 (+1) with 1:0 (-3), 1:0 with 2:0 (+0.25): -1.75 together, all three turn.
        share(tiles, 0, 0, {1, 2, 3});
        share(tiles, 1, 0, {1, 2, 3});
        share(tiles, 1, 0, {5, 5, 5});
        share(tiles, 2, 0, {5, 5, 5});
        CHECK(outside_turns(tiles) == std::vector<std::vector<char>>{{1, 1}, {1, 0}, {1}});
    }
    SUBCASE("one part twice in a tile, through another tile's part") {
        // 0:0 (+1) and 0:1 (-0.5) both meet 1:1 (+2): +2.5, none turns.
        share(tiles, 0, 0, {1, 0, 0});
        share(tiles, 1, 1, {1, 0, 0});
        share(tiles, 0, 1, {2, 0, 0});
        share(tiles, 1, 1, {2, 0, 0});
        CHECK(outside_turns(tiles) == std::vector<std::vector<char>>{{0, 0}, {1, 0}, {0}});
    }
    SUBCASE("places a bit apart are not one vertex") {
        share(tiles, 0, 0, {1, 2, 3});
        share(tiles, 1, 0, {1, 2, std::nextafter(3.f, 4.f)});
        CHECK(outside_turns(tiles) == std::vector<std::vector<char>>{{0, 1}, {1, 0}, {0}});
    }
}

TEST_CASE("a tile's parts: connected by vertices, votes from its window, shared vertices near its edges") {
    // Cells of 1, the window x in [10, 20), y in [0, 20), on a solid block (z up to 9) with the
    // outside above. Strips at z = 10: a long one from x = 6 to 24 (y 8 to 10), through the window
    // and 4 cells past both sides; two that share their x = 16 column (x 14 to 16 and 16 to 18, y
    // 14 to 16); one from x = 22 to 26 (y 2 to 4), more than a cell past the window.
    Mesh m;
    m.cell_size = 1;
    add_strip(m, 6, 24, 8, 10);   // vertices 0 to 56
    add_strip(m, 14, 16, 14, 10); // 57 to 65
    const auto joined = static_cast<std::uint32_t>(m.positions.size());
    add_strip(m, 16, 18, 14, 10); // 66 to 74, its first column made the strip before's last
    for (auto& t : m.triangles)
        for (auto& v : t)
            if (v >= joined && v < joined + 3) v = v - joined + 63;
    const auto far = static_cast<std::uint32_t>(m.positions.size());
    add_strip(m, 22, 26, 2, 10);
    std::vector<std::array<std::int64_t, 3>> solid;
    for (std::int64_t z = 0; z <= 9; ++z)
        for (std::int64_t y = 0; y < 40; ++y)
            for (std::int64_t x = 0; x < 40; ++x) solid.push_back({x, y, z});
    const OutsideSpace outside({40, 40, 40}, solid);
    const TileParts parts = tile_parts(m, {10, 20, 0, 20}, outside);
    REQUIRE(parts.votes.size() == 2);
    const auto vertex = [](int x0, int x, int y) { return std::uint32_t((x - x0) * 3 + y); };
    CHECK(parts.of_vertex[vertex(6, 6, 0)] == TileParts::none); // its squares' centroids over a cell past
    CHECK(parts.of_vertex[vertex(6, 8, 0)] == TileParts::none);
    CHECK(parts.of_vertex[vertex(6, 9, 0)] == 0); // the square from 9 to 10: within a cell
    CHECK(parts.of_vertex[vertex(6, 21, 2)] == 0);
    CHECK(parts.of_vertex[vertex(6, 22, 2)] == TileParts::none);
    CHECK(parts.of_vertex[57] == 1);
    CHECK(parts.of_vertex[joined + 3] == 1); // the second of the joined strips: one part with the first
    CHECK(parts.of_vertex[far] == TileParts::none);
    // Twice the area of the window's triangles, all facing the outside: 10 squares of 2 rows
    // of 2 triangles, 4 squares likewise.
    CHECK(parts.votes[0] == doctest::Approx(40));
    CHECK(parts.votes[1] == doctest::Approx(16));
    // Shared: the vertices within 3 cells of the window's edges (x up to 13 or from 17): the long
    // strip's 10 columns of the 13 in its part (9 to 21, less 14 to 16), the joined strips' 2 (17, 18).
    std::size_t long_strip = 0, inner = 0;
    for (const TileParts::Shared& s : parts.shared) (s.part == 0 ? long_strip : inner) += 1;
    CHECK(long_strip == 10 * 3);
    CHECK(inner == 2 * 3);
    // A turn reaches its part's vertices only.
    const std::vector<char> turn = vertex_turns(parts, {1, 0});
    CHECK(turn[vertex(6, 9, 0)] == 1);
    CHECK(turn[vertex(6, 6, 0)] == 0);
    CHECK(turn[57] == 0);
    // Facing down, the same strips vote against.
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
    const TileParts down = tile_parts(m, {10, 20, 0, 20}, outside);
    CHECK(down.votes[0] == doctest::Approx(-40));
}
