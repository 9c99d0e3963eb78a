// SPDX-License-Identifier: Apache-2.0
// Distances for `lasmesh compare`: exact point-triangle distances on hand-computed cases, the
// searches against brute force, the statistics, surface sampling, and the PLY reader.
#include "io/ply_reader.hpp"
#include "io/ply_writer.hpp"
#include "lasmesh/compare.hpp"
#include "lasmesh/error.hpp"
#include "measure/mesh_distance.hpp"
#include "mesh/marching_cubes.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <random>

using namespace lasmesh;

TEST_CASE("point-triangle distance: hand-computed cases") {
    const Vec3 a{0, 0, 0}, b{4, 0, 0}, c{0, 3, 0};
    CHECK(point_triangle_distance({1, 1, 2}, a, b, c) == doctest::Approx(2));               // above the inside
    CHECK(point_triangle_distance({1, 1, -0.5}, a, b, c) == doctest::Approx(0.5));          // below
    CHECK(point_triangle_distance({1, 1, 0}, a, b, c) == 0);                                // on it
    CHECK(point_triangle_distance({-3, -4, 0}, a, b, c) == doctest::Approx(5));             // nearest a corner
    CHECK(point_triangle_distance({6, 0, 0}, a, b, c) == doctest::Approx(2));               // past corner b
    CHECK(point_triangle_distance({2, -1, 1}, a, b, c) == doctest::Approx(std::sqrt(2.0))); // edge ab
    // Beyond the hypotenuse bc (length 5): the point (4, 3, 0) is 12/5 from it.
    CHECK(point_triangle_distance({4, 3, 0}, a, b, c) == doctest::Approx(2.4));
    CHECK(point_triangle_distance({4, 3, 1.8}, a, b, c) == doctest::Approx(3));
    // Degenerate triangles: a segment and a point.
    CHECK(point_triangle_distance({1, 1, 0}, a, b, {2, 0, 0}) == doctest::Approx(1));
    CHECK(point_triangle_distance({0, 0, 7}, a, a, a) == doctest::Approx(7));
}

TEST_CASE("nearest triangle and nearest point agree with brute force, near and far") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> unit(0, 1);
    Mesh mesh;
    for (int t = 0; t < 500; ++t) {
        const float x = static_cast<float>(10 * unit(rng)), y = static_cast<float>(10 * unit(rng)),
                    z = static_cast<float>(2 * unit(rng));
        const auto v = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.push_back({x, y, z});
        mesh.positions.push_back({x + static_cast<float>(unit(rng)), y, z + 0.2f});
        mesh.positions.push_back({x, y + static_cast<float>(unit(rng)), z - 0.1f});
        mesh.triangles.push_back({v, v + 1, v + 2});
    }
    std::vector<Point3f> points;
    for (int i = 0; i < 2000; ++i)
        points.push_back(
            {static_cast<float>(10 * unit(rng)), static_cast<float>(10 * unit(rng)), static_cast<float>(unit(rng))});
    const TriangleSearch triangles(mesh);
    const PointSearch cloud(points);
    auto to_vec = [](const Point3f& p) { return Vec3{p[0], p[1], p[2]}; };
    for (int q = 0; q < 300; ++q) {
        const double spread = q < 200 ? 12 : 400; // the last ones far outside, like outliers
        const Vec3 p{spread * (unit(rng) - 0.1), spread * (unit(rng) - 0.1), spread * (unit(rng) - 0.5)};
        double tri_best = INFINITY, point_best = INFINITY;
        for (const auto& t : mesh.triangles)
            tri_best =
                std::min(tri_best, point_triangle_distance(p, to_vec(mesh.positions[t[0]]),
                                                           to_vec(mesh.positions[t[1]]), to_vec(mesh.positions[t[2]])));
        for (const Point3f& s : points)
            point_best = std::min(point_best, std::hypot(p[0] - s[0], p[1] - s[1], p[2] - s[2]));
        CAPTURE(q);
        CHECK(triangles.distance(p) == tri_best);
        CHECK(cloud.distance(p) == doctest::Approx(point_best).epsilon(1e-12));
    }
    CHECK(std::isinf(TriangleSearch(Mesh{}).distance({0, 0, 0})));
    CHECK(std::isinf(PointSearch({}).distance({0, 0, 0})));
}

TEST_CASE("distance statistics") {
    std::vector<double> d{4, 1, 3, 2, 0, 5, 6, 7, 8, 9}; // 0..9
    const DistanceStats s = summarize(d, 2.5);
    CHECK(s.count == 10);
    CHECK(s.mean == doctest::Approx(4.5));
    CHECK(s.std == doctest::Approx(std::sqrt(8.25)));
    CHECK(s.median == 4); // nearest rank: the 5th of 10
    CHECK(s.p95 == 9);
    CHECK(s.max == 9);
    CHECK(s.within_1_cell == doctest::Approx(0.3));       // 0, 1, 2
    CHECK(s.within_2_cells == doctest::Approx(0.6));      // 0 .. 5: the limit itself counts as within
    CHECK(s.mean_within_2_cells == doctest::Approx(2.5)); // the mean of 0 .. 5
    std::vector<double> none;
    CHECK(summarize(none, 1).count == 0);
    std::vector<double> one{2};
    CHECK(summarize(one, 0).within_1_cell < 0); // no cell size: not reported
}

TEST_CASE("surface samples: on the triangles, spread by area, the same every time") {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {10, 0, 5}, {13, 0, 5}, {10, 3, 5}}; // areas 0.5 and 4.5
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    const std::vector<Vec3> s = sample_surface(m, 1000);
    REQUIRE(s.size() == 1000);
    int on_small = 0;
    for (const Vec3& p : s) {
        const bool small = p[2] == 0;
        on_small += small;
        const double x = small ? p[0] : (p[0] - 10) / 3, y = small ? p[1] : p[1] / 3;
        CHECK((x >= 0 && y >= 0 && x + y <= 1 + 1e-12));
    }
    CHECK(on_small == 100); // stratified: exactly its share of the area
    CHECK(sample_surface(m, 1000) == s);
}

TEST_CASE("PLY reader: lasmesh's own files, other writers' files, and bad ones") {
    test::TempDir dir;
    test::DenseCells g;
    g.spec.dims = {3, 3, 3};
    g.spec.origin = {500000.25, 6700000.5, 12.125};
    g.spec.cell_size = 0.5;
    g.count.assign(27, 0);
    g.count[13] = 9;
    g.red = g.green = g.blue = std::vector<std::uint64_t>(27, 0);
    g.red[13] = 9 * 200, g.green[13] = 9 * 100, g.blue[13] = 9 * 50, g.color_max_word = 255;
    const Mesh m = extract_closed_surface(g, 1);
    for (bool ascii : {false, true}) {
        write_ply(m, dir.file("m.ply"), ascii);
        const Mesh r = read_ply(dir.file("m.ply"));
        CHECK(r.positions == m.positions);
        CHECK(r.colors == m.colors);
        CHECK(r.triangles == m.triangles);
        CHECK(r.origin == m.origin);
        CHECK(r.cell_size == 0.5);
    }

    // Big-endian doubles, a quad split into two triangles, extra properties and elements.
    std::string be = "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
                     "property double z\nproperty ushort red\nproperty ushort green\nproperty ushort blue\n"
                     "property float confidence\nelement face 1\nproperty list uchar uint vertex_indices\n"
                     "element edge 0\nproperty int vertex1\nend_header\n";
    auto put = [&](const void* data, std::size_t n) {
        const char* c = static_cast<const char*>(data);
        for (std::size_t i = n; i-- > 0;) be += c[i]; // reversed: big-endian on this machine
    };
    const double xyz[4][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 1}};
    for (const auto& v : xyz) {
        for (double c : v) put(&c, 8);
        for (std::uint16_t w : {std::uint16_t{65535}, std::uint16_t{257 * 10}, std::uint16_t{0}}) put(&w, 2);
        const float confidence = 0.5f;
        put(&confidence, 4);
    }
    be += char(4);
    for (std::uint32_t i : {0u, 1u, 2u, 3u}) put(&i, 4);
    test::write_file(dir.file("be.ply"), test::Bytes(reinterpret_cast<const std::byte*>(be.data()),
                                                     reinterpret_cast<const std::byte*>(be.data() + be.size())));
    const Mesh q = read_ply(dir.file("be.ply"));
    REQUIRE(q.positions.size() == 4);
    CHECK(q.positions[3] == std::array<float, 3>{0, 2, 1});
    CHECK(q.colors[0] == std::array<std::uint8_t, 3>{255, 10, 0});
    CHECK(q.triangles == std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}});

    auto write_text = [&](const std::string& text) {
        std::ofstream(dir.file("bad.ply"), std::ios::binary) << text;
        return dir.file("bad.ply");
    };
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    CHECK_THROWS_WITH_AS(read_ply(write_text("solid cube\n")), doctest::Contains("not a PLY file"), Error);
    CHECK_THROWS_WITH_AS(read_ply(write_text("ply\nformat ascii 1.0\n")), doctest::Contains("no end_header"), Error);
    CHECK_THROWS_WITH_AS(read_ply(write_text(head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n")),
                         doctest::Contains("is not below the vertex count 3"), Error);
    CHECK_THROWS_WITH_AS(read_ply(write_text(head + "0 0 0\n1 0 0\n")), doctest::Contains("expected a number"), Error);
    CHECK_THROWS_WITH_AS(read_ply(write_text("ply\nformat binary_little_endian 1.0\nelement vertex 2\n"
                                             "property float x\nproperty float y\nproperty float z\nend_header\n"
                                             "\1\2\3")),
                         doctest::Contains("ends inside vertex 0 property x"), Error);
    CHECK_THROWS_WITH_AS(
        read_ply(write_text("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n")),
        doctest::Contains("no x, y, z"), Error);
    CHECK_THROWS_AS(read_ply(dir.file("missing.ply")), Error);
}
