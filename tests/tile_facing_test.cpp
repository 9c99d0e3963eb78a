// SPDX-License-Identifier: Apache-2.0
// Tiles' sheets made to face as one (src/mesh/tile_facing): a surface faced apart by its tiles is
// turned to face one way, sheets meeting at an angle are left as they are, and a region across a
// fold decides neither for a pair of pieces that share more edges elsewhere nor for a region
// whose other neighbours say otherwise.
#include "mesh/tile_facing.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <map>

using namespace lasmesh;

namespace {

// A flat lattice of unit squares, x in [0, columns), y in [0, rows), at height 0, two triangles
// a square, facing up; the squares of columns [from, to) only.
Mesh plane_columns(int from, int to, int rows) {
    Mesh m;
    std::map<std::pair<int, int>, std::uint32_t> at;
    const auto vertex = [&](int x, int y) {
        const auto [it, fresh] = at.try_emplace({x, y}, static_cast<std::uint32_t>(m.positions.size()));
        if (fresh) m.positions.push_back({float(x), float(y), 0});
        return it->second;
    };
    for (int x = from; x < to; ++x)
        for (int y = 0; y < rows; ++y) {
            const std::uint32_t a = vertex(x, y), b = vertex(x + 1, y), c = vertex(x + 1, y + 1), d = vertex(x, y + 1);
            m.triangles.push_back({a, b, c});
            m.triangles.push_back({a, c, d});
        }
    return m;
}

void turn_all(Mesh& m) {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
}

// Twice the signed area of a triangle's shadow on the ground: > 0 facing up.
double facing_up(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const auto& a = m.positions[t[0]];
    const auto& b = m.positions[t[1]];
    const auto& c = m.positions[t[2]];
    return double(b[0] - a[0]) * (c[1] - a[1]) - double(b[1] - a[1]) * (c[0] - a[0]);
}

// Tiles of one region each, with `area`, and border edges made up to link them: `alike` edges
// along which two tiles' regions run alike, `against` edges along which they face apart.
struct LinkedTiles {
    std::vector<TileRegions> tiles;
    float next = 0; // each edge its own place

    explicit LinkedTiles(const std::vector<double>& areas) {
        for (const double a : areas) {
            tiles.emplace_back();
            tiles.back().area = {a};
        }
    }
    void link(std::size_t a, std::size_t b, int alike, int against) {
        for (int i = 0; i < alike + against; ++i, next += 1) {
            const std::array<float, 3> p{next, 0, 0}, q{next + 0.5f, 0, 0};
            tiles[a].border.push_back({p, q, {0, 0, 1}, 0});
            if (i < alike)
                tiles[b].border.push_back({q, p, {0, 0, 1}, 0});
            else
                tiles[b].border.push_back({p, q, {0, 0, -1}, 0});
        }
    }
    // Border edges that no other tile shares: where the region's surface ends.
    void open(std::size_t k, int count) {
        for (int i = 0; i < count; ++i, next += 1)
            tiles[k].border.push_back({{next, 0, 0}, {next + 0.5f, 0, 0}, {0, 0, 1}, 0});
    }
    std::vector<int> turned() const {
        std::vector<int> which;
        const std::vector<std::vector<char>> turns = facing_turns(tiles);
        for (std::size_t k = 0; k < turns.size(); ++k)
            if (turns[k].at(0)) which.push_back(static_cast<int>(k));
        return which;
    }
};

} // namespace

TEST_CASE("a plane meshed in three tiles, the middle one faced down, is turned to face up as most of it does") {
    std::vector<Mesh> tiles{plane_columns(0, 5, 4), plane_columns(5, 8, 4), plane_columns(8, 12, 4)};
    turn_all(tiles[1]);
    tiles[1].normals.assign(tiles[1].positions.size(), {0, 0, -1});
    // And a wall standing on the first tile's far edge (x = 0), in a fourth tile: four triangles,
    // each a region of its own, each running along the edge it shares with the plane the same
    // way as the plane's triangle: sheets at right angles, which no shared edge joins; it is left
    // as its tile faced it.
    Mesh wall;
    for (int y = 0; y < 4; ++y) {
        const auto base = static_cast<std::uint32_t>(wall.positions.size());
        wall.positions.push_back({0, float(y + 1), 0});
        wall.positions.push_back({0, float(y), 0});
        wall.positions.push_back({0, float(y), 1});
        wall.triangles.push_back({base, base + 1, base + 2}); // (0, y + 1) -> (0, y), as the plane's edge runs
    }
    tiles.push_back(wall);
    std::vector<TileRegions> regions;
    for (const Mesh& m : tiles) regions.push_back(tile_regions(m));
    for (std::size_t k = 0; k < 3; ++k) CHECK(regions[k].area.size() == 1);
    CHECK(regions[0].area[0] == doctest::Approx(20));
    CHECK(regions[1].area[0] == doctest::Approx(12));
    CHECK(regions[0].border.size() == 2 * (5 + 4)); // the lattice's outline
    const std::vector<std::vector<char>> turns = facing_turns(regions);
    CHECK(turns[0] == std::vector<char>{0});
    CHECK(turns[1] == std::vector<char>{1});
    CHECK(turns[2] == std::vector<char>{0});
    CHECK(turns[3] == std::vector<char>(4, 0));
    for (std::size_t k = 0; k < tiles.size(); ++k) turn_regions(tiles[k], regions[k], turns[k]);
    for (std::size_t k = 0; k < 3; ++k)
        for (const auto& t : tiles[k].triangles) CHECK(facing_up(tiles[k], t) > 0);
    for (const auto& n : tiles[1].normals) CHECK(n[2] == 1.0f);
    CHECK(tiles[3].triangles.front() == std::array<std::uint32_t, 3>{0, 1, 2});

    // Faced down by two tiles of three, the plane faces down: the way most of its area faced.
    std::vector<Mesh> down{plane_columns(0, 5, 4), plane_columns(5, 8, 4), plane_columns(8, 12, 4)};
    turn_all(down[0]), turn_all(down[2]);
    std::vector<TileRegions> down_regions;
    for (const Mesh& m : down) down_regions.push_back(tile_regions(m));
    CHECK(facing_turns(down_regions) == std::vector<std::vector<char>>{{0}, {1}, {0}});
}

TEST_CASE("a tile's regions: its triangles joined where two share an edge running opposite ways") {
    // Two squares side by side facing up, and a third beside them faced down: two regions, and
    // the edge between the second and third (running the same way in both) is no border.
    Mesh m = plane_columns(0, 3, 1);
    std::swap(m.triangles[4][1], m.triangles[4][2]);
    std::swap(m.triangles[5][1], m.triangles[5][2]);
    const TileRegions r = tile_regions(m);
    CHECK(r.of_triangle == std::vector<std::uint32_t>{0, 0, 0, 0, 1, 1});
    CHECK(r.area == std::vector<double>{2, 1});
    CHECK(r.border.size() == 8); // the outline of three squares
}

TEST_CASE("a small region across a fold does not turn a piece that shares more edges with the pieces around it") {
    // P1 and P2 (the same tile's two pieces, joined through R) each share 30 edges with Q, running
    // alike; Q and Q2 are one piece (100 edges). A small region s runs alike with P1 (50 edges)
    // and against Q (40): it holds a fold. Joined pair by pair, the heaviest first, s would turn Q
    // and Q2 (its 40 edges come before the 30s, which then disagree); summed, the pieces P1, P2,
    // R and s share 30 + 30 - 40 = 20 edges more alike than against with Q and Q2.
    LinkedTiles t({100, 100, 100, 1, 90, 90}); // P1, P2, R, s, Q, Q2
    t.link(4, 5, 100, 0);
    t.link(0, 2, 100, 0);
    t.link(1, 2, 100, 0);
    t.link(3, 0, 50, 0);
    t.link(3, 4, 0, 40);
    t.link(0, 4, 30, 0);
    t.link(1, 4, 30, 0);
    CHECK(t.turned().empty());
}

TEST_CASE("a region joined the wrong way early is turned back where most of its shared edges say so") {
    // D is the deck; F, a small region holding a fold, runs alike with D (300 edges) and shares
    // 68 edges alike and 187 against with X; X runs alike with A, B and C (75, 68, 81 edges),
    // each alike with D (100 edges). Joined by the largest say first, X follows F against D
    // before A, B and C are joined; they join D as their 100 edges say. X is then turned against
    // all but F: on its own it is turned back (224 edges against 119).
    LinkedTiles t({1000, 5, 20, 50, 50, 50}); // D, F, X, A, B, C
    t.link(1, 0, 300, 0);
    t.link(1, 2, 68, 187);
    t.link(2, 3, 75, 0);
    t.link(2, 4, 68, 0);
    t.link(2, 5, 81, 0);
    for (std::size_t k : {3, 4, 5}) t.link(k, 0, 100, 0);
    CHECK(t.turned().empty());
    // The same with D faced down in its tile: all others are turned instead (D outweighs them).
    for (auto& e : t.tiles[0].border) {
        std::swap(e.from, e.to);
        for (float& c : e.normal) c = -c;
    }
    const std::vector<int> all_but_d{1, 2, 3, 4, 5};
    CHECK(t.turned() == all_but_d);
}

TEST_CASE("two large pieces faced apart by their tiles are not joined by a stray edge") {
    // A, and B1 and B2 (one piece: 100 edges alike), each bordered by 200 edges no other tile
    // shares, share one edge running against each other (a plate's rim cut by a tile border):
    // too little of their borders to turn either. Each keeps its own facing. A piece C against A
    // along 40 edges is turned.
    LinkedTiles t({1000, 450, 450, 10}); // A, B1, B2, C
    t.open(0, 200), t.open(1, 200), t.open(2, 200);
    t.link(1, 2, 100, 0);
    t.link(0, 1, 0, 1);
    t.link(3, 0, 0, 40);
    CHECK(t.turned() == std::vector<int>{3});
}
