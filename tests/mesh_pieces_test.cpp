// SPDX-License-Identifier: Apache-2.0
// Removing small isolated pieces: a big sphere stays whole, a small far one goes, and what
// stays is the same mesh as before, in the same order.
#include "cli/option_parsing.hpp" // the option text parsers, from the command line
#include "lasmesh/error.hpp"
#include "lasmesh/mesh_pieces.hpp"
#include "mesh/marching_cubes.hpp"

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <cmath>

using namespace lasmesh;
using namespace lasmesh::cli;

namespace {

// Balls of the given centres and radii (in cells) in a 40^3 grid of unit cells.
CellGrid balls_grid(const std::vector<std::array<double, 4>>& balls) {
    const std::uint32_t n = 40;
    test::DenseCells g;
    g.spec.dims = {n, n, n};
    g.count.resize(g.spec.cell_count());
    for (std::uint32_t k = 0; k < n; ++k)
        for (std::uint32_t j = 0; j < n; ++j)
            for (std::uint32_t i = 0; i < n; ++i)
                for (const auto& b : balls)
                    if (std::hypot(i + 0.5 - b[0], j + 0.5 - b[1], k + 0.5 - b[2]) < b[3])
                        g.count[(std::uint64_t(k) * n + j) * n + i] = 10;
    return g;
}

} // namespace

TEST_CASE("small isolated pieces are removed, large ones kept unchanged") {
    const Mesh big_alone = extract_closed_surface(balls_grid({{15, 15, 15, 10}}), 1);
    Mesh both = extract_closed_surface(balls_grid({{15, 15, 15, 10}, {34, 34, 34, 2}}), 1);
    REQUIRE(both.triangles.size() > big_alone.triangles.size());

    SUBCASE("a relative threshold removes the small ball only") {
        const PieceCount count = remove_small_pieces(both, parse_min_piece("20%"));
        CHECK(count.pieces == 2);
        CHECK(count.removed == 1);
        CHECK(count.triangles_removed > 0);
        // The big ball comes first in the mesh, so what stays is exactly the big ball's mesh.
        CHECK(both.positions == big_alone.positions);
        CHECK(both.triangles == big_alone.triangles);
    }
    SUBCASE("an absolute threshold in file units") {
        // The small ball's mesh spans about 5 cells (diagonal ~9), the big one about 21 (~36).
        CHECK(remove_small_pieces(both, parse_min_piece("12")).removed == 1);
        CHECK(both.triangles == big_alone.triangles);
    }
    SUBCASE("zero keeps everything") {
        const Mesh before = both;
        const PieceCount count = remove_small_pieces(both, parse_min_piece("0"));
        CHECK(count.pieces == 2);
        CHECK(count.removed == 0);
        CHECK(both.triangles == before.triangles);
    }
    SUBCASE("a threshold above every piece leaves an empty mesh") {
        remove_small_pieces(both, parse_min_piece("100"));
        CHECK(both.positions.empty());
        CHECK(both.triangles.empty());
    }
}

TEST_CASE("--min-piece text") {
    CHECK(parse_min_piece("5%").relative);
    CHECK(parse_min_piece("5%").value == doctest::Approx(0.05));
    CHECK(!parse_min_piece("2.5").relative);
    CHECK(parse_min_piece("2.5").value == 2.5);
    for (const char* bad : {"", "%", "-1", "abc", "5%%", "101%", "nan", "inf", "1e400"})
        CHECK_THROWS_AS(parse_min_piece(bad), Error);
}

TEST_CASE("sheets that meet at an edge without sharing vertices are one piece; a far one is not") {
    // A 2 x 2 floor and a 2 x 2 wall standing on its edge, 0.05 apart (under the cell of 0.1), and
    // a small square 5 away: each square's diagonal is 2.83, the floor and wall together 3.46.
    Mesh m;
    m.cell_size = 0.1;
    const auto square = [&](std::array<float, 3> corner, std::array<float, 3> u, std::array<float, 3> v) {
        const auto at = [&](float a, float b) {
            return std::array<float, 3>{corner[0] + a * u[0] + b * v[0], corner[1] + a * u[1] + b * v[1],
                                        corner[2] + a * u[2] + b * v[2]};
        };
        const auto first = static_cast<std::uint32_t>(m.positions.size());
        for (const auto& p : {at(0, 0), at(1, 0), at(1, 1), at(0, 1)}) m.positions.push_back(p);
        m.triangles.push_back({first, first + 1, first + 2});
        m.triangles.push_back({first, first + 2, first + 3});
    };
    square({0, 0, 0}, {2, 0, 0}, {0, 2, 0});         // floor
    square({2.05f, 0, 0.05f}, {0, 2, 0}, {0, 0, 2}); // wall on its edge
    square({8, 8, 0}, {0.5, 0, 0}, {0, 0.5, 0});     // far away
    Mesh copy = m;
    const PieceCount count = remove_small_pieces(copy, parse_min_piece("3"));
    CHECK(count.pieces == 2); // floor and wall joined
    CHECK(count.removed == 1);
    CHECK(copy.triangles.size() == 4);
    m.cell_size = 0.01; // a gap of 5 cells: apart, and each too small
    CHECK(remove_small_pieces(m, parse_min_piece("3")).removed == 3);
}
