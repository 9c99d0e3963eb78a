// SPDX-License-Identifier: Apache-2.0
// Thin parts: the eigenvalues their test rests on, and the bricks found on the generated deck:
// the railings' (thinner than a cell), not the deck's middle, a container's top or a pipe's.
#include "grid/thin_parts.hpp"
#include "lasgen/scene.hpp"
#include "lasmesh/grid.hpp"
#include "mesh/marching_cubes.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

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

TEST_CASE("thin bricks on the deck: the railings', not the deck's, a container's or a pipe's") {
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
    const std::vector<std::uint64_t> thin = thin_bricks(cells, automatic_iso(cells));
    REQUIRE(std::is_sorted(thin.begin(), thin.end()));
    const auto brick_at = [&](const lasmesh::Vec3& local) {
        const lasmesh::Vec3 w = lasgen::to_world(deck, local);
        std::array<std::uint64_t, 3> b{};
        for (int a = 0; a < 3; ++a)
            b[a] = static_cast<std::uint64_t>(std::floor((w[a] - cells.spec.origin[a]) / cells.spec.cell_size)) >>
                   CellGrid::brick_bits;
        return (b[2] * cells.bricks[1] + b[1]) * cells.bricks[0] + b[0];
    };
    const auto is_thin = [&](const lasmesh::Vec3& local) {
        return std::binary_search(thin.begin(), thin.end(), brick_at(local));
    };
    int rails = 0;
    for (double x = 3.3; x < 40; x += 4) rails += is_thin({x, 0.3, 1.1}) + is_thin({x, 23.7, 0.55});
    CHECK(rails >= 16);                // of 18 points along the top and middle rails
    CHECK(!is_thin({30, 12, 0}));      // the deck's middle
    CHECK(!is_thin({12, 4.25, 2.6}));  // the long container's top
    CHECK(!is_thin({20, 21.5, 1.05})); // the 50 cm pipe's top
    CHECK(!is_thin({51, 6, 3.5}));     // the deckhouse's wall
    // A small share of the occupied bricks: the refinement stays where it is needed.
    const auto occupied =
        std::count_if(thin.begin(), thin.end(), [&](std::uint64_t key) { return cells.brick_table.find(key) != 0; });
    CHECK(occupied < static_cast<std::ptrdiff_t>(cells.brick_keys.size() / 5));
}
