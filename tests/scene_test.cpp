// SPDX-License-Identifier: Apache-2.0
// The scene generator: deterministic, inside its own header bounds, and shaped as documented.
#include "lasgen/scene.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <cmath>

TEST_CASE("generated points depend only on seed and index") {
    lasgen::SceneOptions o;
    const lasgen::Scene deck = lasgen::make_scene(o);
    for (std::uint64_t i : {0ull, 1ull, 12345ull, 99999999ull}) {
        const auto a = lasgen::generate_point(deck, 7, i), b = lasgen::generate_point(deck, 7, i);
        CHECK(a.position == b.position);
        CHECK(a.color == b.color);
    }
    CHECK(lasgen::generate_point(deck, 7, 5).position != lasgen::generate_point(deck, 8, 5).position);
    lasgen::LasLayout layout;
    CHECK(test::make_las(layout, deck, 500, 3) == test::make_las(layout, deck, 500, 3));
}

TEST_CASE("every point lies inside the scene bounds") {
    for (auto kind :
         {lasgen::SceneKind::sphere, lasgen::SceneKind::box, lasgen::SceneKind::torus, lasgen::SceneKind::deck}) {
        lasgen::SceneOptions o;
        o.kind = kind;
        o.noise = 0.05;
        const lasgen::Scene s = lasgen::make_scene(o);
        CAPTURE(s.name);
        lasmesh::Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
        for (std::uint64_t i = 0; i < 100000; ++i) {
            const auto p = lasgen::generate_point(s, 1, i);
            for (int a = 0; a < 3; ++a) {
                REQUIRE(p.position[a] >= s.min[a]);
                REQUIRE(p.position[a] <= s.max[a]);
                lo[a] = std::min(lo[a], p.position[a]);
                hi[a] = std::max(hi[a], p.position[a]);
            }
        }
        // The bounds are tight: 100k points come within 20 cm of every side.
        for (int a = 0; a < 3; ++a) {
            CHECK(lo[a] - s.min[a] < 0.2);
            CHECK(s.max[a] - hi[a] < 0.2);
        }
    }
}

TEST_CASE("a sphere without noise lies on its surface") {
    lasgen::SceneOptions o;
    o.kind = lasgen::SceneKind::sphere;
    o.size = 6;
    o.origin = {10, 20, 30};
    const lasgen::Scene s = lasgen::make_scene(o);
    for (std::uint64_t i = 0; i < 1000; ++i) {
        const auto p = lasgen::generate_point(s, 2, i);
        const double dx = p.position[0] - 10, dy = p.position[1] - 20, dz = p.position[2] - 30;
        REQUIRE(std::sqrt(dx * dx + dy * dy + dz * dz) == doctest::Approx(3.0).epsilon(1e-12));
        REQUIRE(p.color == o.color);
    }
}

TEST_CASE("the deck's density varies several-fold and it has a few outliers") {
    lasgen::SceneOptions o;
    o.origin = {0, 0, 0};
    const lasgen::Scene deck = lasgen::make_scene(o);
    // Count deck-plane points (z near 0 after the small tilt) in two 4 m strips across the deck.
    int dense = 0, sparse = 0, outliers = 0;
    const int n = 400000;
    for (int i = 0; i < n; ++i) {
        const auto p = lasgen::generate_point(deck, 1, i);
        if (p.classification == 7) ++outliers;
        if (std::abs(p.position[2] + 0.0087 * p.position[0]) > 0.1) continue;
        if (p.position[0] > 22 && p.position[0] < 26) ++dense;
        if (p.position[0] > 60 && p.position[0] < 64) ++sparse;
    }
    CHECK(dense > 3 * sparse);
    CHECK(outliers > 0);
    CHECK(outliers < n / 100);
}
