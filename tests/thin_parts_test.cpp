// SPDX-License-Identifier: Apache-2.0
// Thin parts: the eigenvalues their test rests on, and the cells found on the generated deck:
// the railings' (thinner than a cell), not the deck's middle, a container's top or a pipe's.
#include "byte_order.hpp"
#include "grid/cell_set.hpp"
#include "grid/records_in_cells.hpp"
#include "grid/thin_parts.hpp"
#include "lasgen/scene.hpp"
#include "lasmesh/grid.hpp"
#include "mesh/marching_cubes.hpp"
#include "mesh/mesh_edit.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <tuple>

using namespace lasmesh;

TEST_CASE("symmetric eigenvalues: diagonal, rotated, repeated") {
    auto e = symmetric_eigenvalues({{{1, 0, 0}, {0, 3, 0}, {0, 0, 2}}});
    CHECK(e[0] == doctest::Approx(3));
    CHECK(e[1] == doctest::Approx(2));
    CHECK(e[2] == doctest::Approx(1));
    // R diag(5, 2, 0.5) R^T, R a rotation by 30 degrees about z then 40 about x.
    const double c1 = std::cos(0.5236), s1 = std::sin(0.5236), c2 = std::cos(0.6981), s2 = std::sin(0.6981);
    const double r[3][3] = {{c1, -s1, 0}, {c2 * s1, c2 * c1, -s2}, {s2 * s1, s2 * c1, c2}};
    const double d[3] = {5, 2, 0.5};
    std::array<std::array<double, 3>, 3> a{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) a[i][j] += r[i][k] * d[k] * r[j][k];
    e = symmetric_eigenvalues(a);
    CHECK(e[0] == doctest::Approx(5));
    CHECK(e[1] == doctest::Approx(2));
    CHECK(e[2] == doctest::Approx(0.5));
    e = symmetric_eigenvalues({{{2, 0, 0}, {0, 2, 0}, {0, 0, 7}}});
    CHECK(e[0] == doctest::Approx(7));
    CHECK(e[1] == doctest::Approx(2));
    CHECK(e[2] == doctest::Approx(2));
}

TEST_CASE("blocks around cells: reach, clipping at the grid, brick numbering, ascending and unique") {
    // Cells (1, 1, 0) and (2, 1, 0) in a 4 x 3 x 2 grid, reach 1: x 0-3, y 0-2, z 0-1, all 24.
    std::vector<std::uint64_t> keys = blocks_around({{1, 1, 0}, {2, 1, 0}}, {4, 3, 2}, 0, 1);
    CHECK(keys.size() == 24);
    CHECK(std::is_sorted(keys.begin(), keys.end()));
    // Cell (0, 0, 0), reach 1, in 5 x 5 x 5: the 2 x 2 x 2 corner, keys (z * 5 + y) * 5 + x.
    keys = blocks_around({{0, 0, 0}}, {5, 5, 5}, 0, 1);
    CHECK(keys == std::vector<std::uint64_t>{0, 1, 5, 6, 25, 26, 30, 31});
    // Reach 0: the cells themselves, each once.
    keys = blocks_around({{3, 2, 1}, {3, 2, 1}}, {5, 5, 5}, 0, 0);
    CHECK(keys == std::vector<std::uint64_t>{(1 * 5 + 2) * 5 + 3});
    // Bricks of 4 cells (shift 2): cells 5 and 7 on x are both in brick 1; with reach 1, bricks 0-2.
    keys = blocks_around({{5, 0, 0}, {7, 0, 0}}, {3, 1, 1}, 2, 1);
    CHECK(keys == std::vector<std::uint64_t>{0, 1, 2});
}

TEST_CASE("cell set: exactly its cells, found by the bits per brick and by the hash") {
    // A grid whose sides are not whole bricks, cells drawn at random (some bricks full, most
    // empty), and a cluster around a corner: every cell of the grid asked about, both ways.
    const std::array<std::int64_t, 3> dims{23, 9, 14};
    std::mt19937_64 random(7);
    std::set<std::uint64_t> chosen;
    for (int i = 0; i < 300; ++i) chosen.insert(random() % std::uint64_t(dims[0] * dims[1] * dims[2]));
    for (std::int64_t z = 10; z < 14; ++z)
        for (std::int64_t y = 4; y < 8; ++y)
            for (std::int64_t x = 20; x < 23; ++x) chosen.insert(std::uint64_t((z * dims[1] + y) * dims[0] + x));
    const std::vector<std::uint64_t> keys(chosen.begin(), chosen.end());
    for (const std::uint64_t bitmap_limit : {CellSet::max_bitmap_bricks, std::uint64_t{0}}) {
        CAPTURE(bitmap_limit);
        const CellSet set(keys, dims, bitmap_limit);
        CHECK(set.has_bitmap() == (bitmap_limit > 0));
        std::size_t found = 0, wrong = 0;
        for (std::int64_t z = 0; z < dims[2]; ++z)
            for (std::int64_t y = 0; y < dims[1]; ++y)
                for (std::int64_t x = 0; x < dims[0]; ++x) {
                    const bool in = set.contains(std::uint64_t(x), std::uint64_t(y), std::uint64_t(z));
                    found += in;
                    wrong += in != chosen.contains(std::uint64_t((z * dims[1] + y) * dims[0] + x));
                }
        CHECK(found == chosen.size());
        CHECK(wrong == 0);
    }
    CHECK_FALSE(CellSet({}, dims).contains(0, 0, 0));
}

TEST_CASE("records in cells: exactly the records whose cell is in the set, in their order, at any raw span") {
    // Records of 26 bytes (X, Y, Z, then the record's number) in and around a 37 x 11 x 6 grid,
    // some on the cells' starts and ends and outside on every side; kept by the rule of
    // AxisCells::cell_of. At millimetres the table has a run for every raw value; at 0.1 um the
    // grid spans 37 million raw values along x and a run holds several, which the starts settle.
    const std::array<std::int64_t, 3> dims{37, 11, 6};
    std::mt19937_64 random(11);
    std::set<std::uint64_t> chosen;
    for (int i = 0; i < 700; ++i) chosen.insert(random() % std::uint64_t(dims[0] * dims[1] * dims[2]));
    const std::vector<std::uint64_t> keys(chosen.begin(), chosen.end());
    const CellSet set(keys, dims);
    GridSpec spec;
    spec.origin = {1000.3, -20.7, 5.1};
    spec.cell_size = 0.0999;
    spec.dims = {37, 11, 6};
    constexpr std::size_t length = 26, count = 20000; // blocks of 4,096 records and a part of one
    for (const double scale : {0.001, 1e-7}) {
        CAPTURE(scale);
        const std::array<double, 3> offset{1000, -21, 5};
        std::array<AxisCells, 3> axes;
        for (int a = 0; a < 3; ++a) axes[a] = axis_cells(spec, a, scale, offset[a]);
        std::vector<std::byte> records(count * length);
        std::vector<std::uint32_t> expected;
        for (std::uint32_t i = 0; i < count; ++i) {
            std::array<std::int64_t, 3> raw{}, cell{};
            for (int a = 0; a < 3; ++a) {
                const std::vector<std::int64_t>& starts = axes[a].starts;
                const std::int64_t first = starts.front(), last = starts.back();
                const std::uint64_t pick = random() % 10;
                if (pick == 0) // a cell's start or the last raw value of the one before
                    raw[a] = starts[random() % starts.size()] - std::int64_t(random() % 2);
                else if (pick == 1) // outside, just or far
                    raw[a] =
                        random() % 2 ? first - 1 - std::int64_t(random() % 1000) : last + std::int64_t(random() % 1000);
                else
                    raw[a] = first + std::int64_t(random() % std::uint64_t(last - first));
                cell[a] = axes[a].cell_of(raw[a]);
                store_le<std::int32_t>(records.data() + i * length + 4 * a, std::int32_t(raw[a]));
            }
            std::memcpy(records.data() + i * length + 12, &i, sizeof i);
            if (cell[0] >= 0 && cell[1] >= 0 && cell[2] >= 0 &&
                chosen.contains(std::uint64_t((cell[2] * dims[1] + cell[1]) * dims[0] + cell[0])))
                expected.push_back(i);
        }
        REQUIRE(expected.size() > 1000);
        const RecordsInCells in_set(axes, set, length);
        const std::size_t kept = in_set.keep(records.data(), count);
        std::vector<std::uint32_t> got(kept);
        for (std::size_t k = 0; k < kept; ++k) std::memcpy(&got[k], records.data() + k * length + 12, sizeof got[k]);
        CHECK(got == expected);
    }
}

TEST_CASE("triangles kept by the cell or brick of their centroid, in their order, unused vertices dropped") {
    // Three triangles in cells of 1 (4 x 3 x 4: x and y count differently, so a key with its axes
    // swapped names other cells): centroids in cells (0, 0, 0), (1, 0, 0), (2, 1, 0).
    Mesh mesh;
    mesh.positions = {{0.1f, 0.1f, 0.5f}, {0.5f, 0.9f, 0.5f}, {0.9f, 0.1f, 0.5f}, // cell (0, 0, 0)
                      {1.1f, 0.1f, 0.5f}, {1.5f, 0.9f, 0.5f}, {1.9f, 0.1f, 0.5f}, // (1, 0, 0)
                      {2.1f, 1.1f, 0.5f}, {2.5f, 1.9f, 0.5f}, {2.9f, 1.1f, 0.5f}, // (2, 1, 0)
                      {3.5f, 2.5f, 3.5f}};                                        // no triangle's
    mesh.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
    GridSpec spec;
    spec.dims = {4, 3, 4};
    const std::uint64_t cell_100 = 1, cell_210 = 1 * 4 + 2;
    Mesh inside = mesh;
    keep_triangles_in_blocks(inside, spec, 0, {cell_100, cell_210}, true);
    REQUIRE(inside.triangles.size() == 2);
    CHECK(inside.positions.size() == 6);
    CHECK(inside.positions[0] == mesh.positions[3]);
    CHECK(inside.triangles[1] == std::array<std::uint32_t, 3>{3, 4, 5});
    Mesh outside = mesh;
    keep_triangles_in_blocks(outside, spec, 0, {cell_100, cell_210}, false);
    REQUIRE(outside.triangles.size() == 1);
    CHECK(outside.positions[2] == mesh.positions[2]);
    // Bricks of 2 cells (shift 1): brick (0, 0, 0) holds the first two, brick (1, 0, 0) the third.
    Mesh bricks = mesh;
    keep_triangles_in_blocks(bricks, spec, 1, {0}, true);
    CHECK(bricks.triangles.size() == 2);
}

TEST_CASE("thin cells on the deck: the railings', not the deck's, a container's or a pipe's") {
    test::TempDir dir;
    lasgen::SceneOptions options;
    options.origin = {431250, 6700200, 10};
    const lasgen::Scene deck = lasgen::make_scene(options);
    lasgen::LasLayout layout;
    for (int a = 0; a < 3; ++a) layout.offset[a] = std::floor(deck.min[a]);
    test::write_file(dir.file("deck.las"), test::make_las(layout, deck, 2'000'000));
    AccumulateOptions grid;
    grid.grid = GridRequest::longest(512); // cells of 12.5 cm: the railings' 4-6 cm are thinner
    const CellGrid cells = test::accumulate_file(dir.file("deck.las"), grid);
    const std::array<std::int64_t, 3> dims{cells.spec.dims[0], cells.spec.dims[1], cells.spec.dims[2]};
    const std::vector<std::uint64_t> thin = blocks_around(thin_cells(cells, automatic_iso(cells)), dims, 0, 1);
    REQUIRE(std::is_sorted(thin.begin(), thin.end()));
    const auto cell_at = [&](const lasmesh::Vec3& local) {
        const lasmesh::Vec3 w = lasgen::to_world(deck, local);
        std::array<std::uint64_t, 3> c{};
        for (int a = 0; a < 3; ++a)
            c[a] = static_cast<std::uint64_t>(std::floor((w[a] - cells.spec.origin[a]) / cells.spec.cell_size));
        return (c[2] * std::uint64_t(dims[1]) + c[1]) * std::uint64_t(dims[0]) + c[0];
    };
    const auto is_thin = [&](const lasmesh::Vec3& local) {
        return std::binary_search(thin.begin(), thin.end(), cell_at(local));
    };
    int rails = 0;
    for (double x = 3.3; x < 40; x += 4) rails += is_thin({x, 0.3, 1.1}) + is_thin({x, 23.7, 0.55});
    CHECK(rails >= 16);                // of 18 points along the top and middle rails
    CHECK(!is_thin({30, 12, 0}));      // the deck's middle
    CHECK(!is_thin({12, 4.25, 2.6}));  // the long container's top
    CHECK(!is_thin({20, 21.5, 1.05})); // the 50 cm pipe's top
    CHECK(!is_thin({51, 6, 3.5}));     // the deckhouse's wall
    // The deck's edges, where the deck ends part-way through a row of cells: a plane's edge, not
    // a rail (the posts' feet, within 30 cm of x = 0.5, 2.5, ..., left out), along x and along y.
    const std::vector<std::array<std::int64_t, 3>> thin_only = thin_cells(cells, automatic_iso(cells));
    std::vector<std::uint64_t> thin_keys;
    for (const auto& c : thin_only)
        thin_keys.push_back((std::uint64_t(c[2]) * std::uint64_t(dims[1]) + std::uint64_t(c[1])) *
                                std::uint64_t(dims[0]) +
                            std::uint64_t(c[0]));
    std::sort(thin_keys.begin(), thin_keys.end());
    int edges = 0, thin_edges = 0;
    for (double x = 1; x < 63; x += 0.125) {
        if (std::abs(std::remainder(x - 0.5, 2.0)) < 0.3) continue;
        for (const double y : {0.01, 23.99}) {
            ++edges;
            thin_edges += std::binary_search(thin_keys.begin(), thin_keys.end(), cell_at({x, y, 0}));
        }
    }
    for (double y = 1; y < 23; y += 0.125) // and its short edges, lines along y
        for (const double x : {0.01, 63.99}) {
            ++edges;
            thin_edges += std::binary_search(thin_keys.begin(), thin_keys.end(), cell_at({x, y, 0}));
        }
    CHECK(edges > 900);
    CHECK(thin_edges < edges / 10); // taken for lines, 64% of them are
    // A small share of the occupied cells: the refinement stays where it is needed.
    const auto occupied = std::count_if(thin.begin(), thin.end(), [&](std::uint64_t key) {
        const auto d = static_cast<std::uint64_t>(dims[0]), e = static_cast<std::uint64_t>(dims[1]);
        return cells.find(std::int64_t(key % d), std::int64_t(key / d % e), std::int64_t(key / d / e)) != nullptr;
    });
    CHECK(occupied < static_cast<std::ptrdiff_t>(cells.occupied_cells() / 10));
}

TEST_CASE("thin cells: a rail's junction with a post between them, a plate the rail ends on not") {
    // Cells of 1, 32 x 12 x 12, 8 points each at its centre: a rail along x at y = 5, z = 8 (x
    // 0-19), a post under it at x = 10 (z 2-7), and a plate at z = 8 the rail runs into (x 20-29,
    // y 0-11). The rail's and the post's cells lie along lines; where they meet, and at the post's
    // top, the cells around are no line, yet thin cells lie on opposite sides of them.
    GridSpec spec;
    spec.dims = {32, 12, 12};
    std::vector<std::uint64_t> count(spec.cell_count(), 0);
    const auto set = [&](std::uint64_t x, std::uint64_t y, std::uint64_t z) {
        count[(z * spec.dims[1] + y) * spec.dims[0] + x] = 8;
    };
    for (std::uint64_t x = 0; x < 20; ++x) set(x, 5, 8);
    for (std::uint64_t z = 2; z < 8; ++z) set(10, 5, z);
    for (std::uint64_t x = 20; x < 30; ++x)
        for (std::uint64_t y = 0; y < 12; ++y) set(x, y, 8);
    // And a small plate beside the rail, two cells off: thin cells around it, on one side only.
    for (std::uint64_t x = 3; x < 7; ++x)
        for (std::uint64_t y = 7; y < 9; ++y) set(x, y, 8);
    const std::vector<std::array<std::int64_t, 3>> thin = thin_cells(test::grid_from_counts(spec, count), 1);
    REQUIRE(std::is_sorted(thin.begin(), thin.end(), [](const auto& a, const auto& b) {
        return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]);
    }));
    const auto has = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
        return std::find(thin.begin(), thin.end(), std::array<std::int64_t, 3>{x, y, z}) != thin.end();
    };
    for (std::int64_t x = 1; x < 18; ++x) CHECK(has(x, 5, 8)); // the rail, its junction included
    for (std::int64_t z = 3; z < 8; ++z) CHECK(has(10, 5, z)); // the post, up to the junction
    // The plate: neither its middle nor its edge where the rail ends (thin cells on one side only).
    CHECK(!has(25, 5, 8));
    CHECK(!has(20, 5, 8));
    CHECK(!has(21, 5, 8));
    CHECK(!has(20, 4, 8));
    for (const auto& c : thin) CHECK(c[0] < 21);
    for (std::int64_t x = 3; x < 7; ++x) CHECK(!has(x, 7, 8));
}

TEST_CASE("thin cells: a rail along a diagonal is thin, a plane's diagonal edge is not") {
    // Cells of 1, 24 x 24 x 12, 8 points each at its centre. A rail along the diagonal x = y at
    // z = 8 (a staircase of cells, two a step), and a plate at z = 3 whose edge runs along the
    // same diagonal (the cells with y <= x). Told apart only along the line's own direction: across
    // a diagonal rail, a line taken along x would find the rail's own cells beside it.
    GridSpec spec;
    spec.dims = {24, 24, 12};
    std::vector<std::uint64_t> count(spec.cell_count(), 0);
    const auto set = [&](std::uint64_t x, std::uint64_t y, std::uint64_t z) {
        count[(z * spec.dims[1] + y) * spec.dims[0] + x] = 8;
    };
    for (std::uint64_t k = 2; k < 21; ++k) set(k, k, 8), set(k + 1, k, 8);
    for (std::uint64_t y = 2; y < 22; ++y)
        for (std::uint64_t x = y; x < 22; ++x) set(x, y, 3);
    const std::vector<std::array<std::int64_t, 3>> thin = thin_cells(test::grid_from_counts(spec, count), 1);
    const auto has = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
        return std::find(thin.begin(), thin.end(), std::array<std::int64_t, 3>{x, y, z}) != thin.end();
    };
    std::size_t rail = 0, edge = 0;
    for (std::int64_t k = 5; k < 18; ++k) rail += has(k, k, 8) + has(k + 1, k, 8), edge += has(k, k, 3);
    CHECK(rail >= 24); // of 26
    CHECK(edge <= 2);  // of 13
}
