// SPDX-License-Identifier: Apache-2.0
// Marching cubes on synthetic fields: closed, consistently oriented, outward-facing meshes with
// the right topology, identical for any thread count.
#include "cli/option_parsing.hpp" // the option text parsers, from the command line
#include "lasmesh/error.hpp"
#include "mesh/marching_cubes.hpp"
#include "mesh/marching_cubes_table.hpp"

#include <doctest/doctest.h>

#include "test_support.hpp"
#include <tbb/task_arena.h>

#include <cmath>
#include <functional>
#include <map>

using namespace lasmesh;
using namespace lasmesh::cli;

namespace {

// A grid of n^3 unit cells whose counts come from `field` at the cell centres.
CellGrid field_grid(std::uint32_t n, const std::function<double(double, double, double)>& field) {
    test::DenseCells g;
    g.spec.dims = {n, n, n};
    g.spec.cell_size = 1;
    g.count.resize(g.spec.cell_count());
    for (std::uint32_t k = 0; k < n; ++k)
        for (std::uint32_t j = 0; j < n; ++j)
            for (std::uint32_t i = 0; i < n; ++i)
                g.count[(std::uint64_t(k) * n + j) * n + i] =
                    static_cast<std::uint64_t>(std::max(0.0, std::round(field(i + 0.5, j + 0.5, k + 0.5))));
    return g;
}

struct Topology {
    bool closed = true;      // every edge has exactly two triangles
    bool oriented = true;    // ... and they use it in opposite directions
    bool degenerate = false; // a triangle with zero area or repeated vertices
    long euler = 0;          // V - E + F
};

Topology topology(const Mesh& m) {
    Topology t;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& tri : m.triangles) {
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) t.degenerate = true;
        const auto &a = m.positions[tri[0]], &b = m.positions[tri[1]], &c = m.positions[tri[2]];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        if (n[0] * n[0] + n[1] * n[1] + n[2] * n[2] <= 0) t.degenerate = true;
        for (int e = 0; e < 3; ++e) ++directed[{tri[e], tri[(e + 1) % 3]}];
    }
    long undirected = 0;
    for (const auto& [edge, uses] : directed) {
        if (uses != 1) t.oriented = false;
        const auto reverse = directed.find({edge.second, edge.first});
        if (reverse == directed.end()) t.closed = false;
        if (edge.first < edge.second || reverse == directed.end()) ++undirected;
    }
    t.euler = static_cast<long>(m.positions.size()) - undirected + static_cast<long>(m.triangles.size());
    return t;
}

void check_closed_surface(const Mesh& m, long euler) {
    const Topology t = topology(m);
    CHECK(t.closed);
    CHECK(t.oriented);
    CHECK(!t.degenerate);
    CHECK(t.euler == euler);
}

double sphere(double x, double y, double z, double cx, double cy, double cz, double r) {
    const double d = std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz));
    return 10 * (r - d); // 10 points per cell of depth: a smooth ramp through the iso value
}

} // namespace

TEST_CASE("the derived case table: every corner configuration gives a closed, oriented surface") {
    // Each of the 256 cases as a 2 x 2 x 2 grid inside the empty padding: the whole surface of
    // the inside cells must close up, whatever the ambiguous faces.
    for (int mask = 0; mask < 256; ++mask) {
        CAPTURE(mask);
        test::DenseCells g;
        g.spec.dims = {2, 2, 2};
        g.count.resize(8);
        for (int c = 0; c < 8; ++c) g.count[c] = (mask >> c) & 1 ? 10 : 0;
        const Mesh m = extract_closed_surface(g, 5);
        const Topology t = topology(m);
        REQUIRE(t.closed);
        REQUIRE(t.oriented);
        REQUIRE(!t.degenerate);
        CHECK((m.triangles.empty() == (mask == 0)));
    }
    CHECK(case_table().triangles[0].empty());
    CHECK(case_table().triangles[255].empty());
    CHECK(case_table().triangles[1].size() == 1);
}

constexpr VertexPlacement both_placements[] = {VertexPlacement::surface, VertexPlacement::iso};

TEST_CASE("a sphere: closed, genus 0, normals outward, vertices on the sphere") {
    const CellGrid g = field_grid(24, [](double x, double y, double z) { return sphere(x, y, z, 12, 12, 12, 8); });
    for (VertexPlacement placement : both_placements) {
        const Mesh m = extract_closed_surface(g, 4.5, placement);
        check_closed_surface(m, 2);
        for (const auto& tri : m.triangles) {
            const auto &a = m.positions[tri[0]], &b = m.positions[tri[1]], &c = m.positions[tri[2]];
            const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
            const double out[3] = {a[0] - 12, a[1] - 12, a[2] - 12};
            REQUIRE(n[0] * out[0] + n[1] * out[1] + n[2] * out[2] > 0); // from dense inside to empty outside
        }
    }
    const Mesh m = extract_closed_surface(g, 4.5, VertexPlacement::iso);
    // Where the field is 4.5 the distance from the centre is 8 - 0.45.
    for (const auto& p : m.positions) {
        const double d = std::sqrt((p[0] - 12) * (p[0] - 12) + (p[1] - 12) * (p[1] - 12) + (p[2] - 12) * (p[2] - 12));
        REQUIRE(std::abs(d - 7.55) < 0.2);
    }
}

TEST_CASE("a torus has Euler characteristic 0, a box and touching spheres close up") {
    const CellGrid torus = field_grid(32, [](double x, double y, double z) {
        const double ring = std::sqrt((x - 16) * (x - 16) + (y - 16) * (y - 16)) - 9;
        return 10 * (4 - std::sqrt(ring * ring + (z - 16) * (z - 16)));
    });
    for (VertexPlacement placement : both_placements)
        check_closed_surface(extract_closed_surface(torus, 5, placement), 0);

    const CellGrid box = field_grid(16, [](double x, double y, double z) {
        return (x > 3 && x < 12 && y > 4 && y < 13 && z > 2 && z < 10) ? 50 : 0;
    });
    for (VertexPlacement placement : both_placements)
        check_closed_surface(extract_closed_surface(box, 25, placement), 2);

    // Two spheres that just touch: one or two pieces, but always closed and oriented.
    const CellGrid twins = field_grid(32, [](double x, double y, double z) {
        return std::max(sphere(x, y, z, 10, 16, 16, 6), sphere(x, y, z, 22, 16, 16, 6));
    });
    const Topology t = topology(extract_closed_surface(twins, 0.5));
    CHECK(t.closed);
    CHECK(t.oriented);
    CHECK(!t.degenerate);
    CHECK((t.euler == 2 || t.euler == 4));
}

TEST_CASE("random smooth fields and integer iso ties give closed, oriented surfaces") {
    for (int seed = 1; seed <= 5; ++seed) {
        CAPTURE(seed);
        const CellGrid g = field_grid(20, [seed](double x, double y, double z) {
            return 6 + 5 * std::sin(0.7 * x + seed) * std::cos(0.5 * y - seed) + 4 * std::sin(0.6 * z * seed);
        });
        for (double iso : {3.0, 6.0, 7.25}) // integers tie with many counts: inside means > iso
            for (VertexPlacement placement : both_placements) {
                CAPTURE(iso);
                CAPTURE(static_cast<int>(placement));
                const Topology t = topology(extract_closed_surface(g, iso, placement));
                CHECK(t.closed);
                CHECK(t.oriented);
                CHECK(!t.degenerate);
            }
    }
}

TEST_CASE("the mesh is identical for 1, 2 and 16 threads") {
    const CellGrid g = field_grid(40, [](double x, double y, double z) {
        return 8 + 6 * std::sin(0.4 * x) * std::sin(0.3 * y) + 3 * std::cos(0.5 * z);
    });
    auto run = [&](int threads) {
        tbb::task_arena arena(threads);
        Mesh m;
        arena.execute([&] { m = extract_closed_surface(g, 8); }); // surface placement: reads beyond the edge
        return m;
    };
    const Mesh one = run(1);
    REQUIRE(!one.triangles.empty());
    for (int threads : {2, 16}) {
        const Mesh m = run(threads);
        CHECK(m.positions == one.positions);
        CHECK(m.triangles == one.triangles);
    }
}

TEST_CASE("surface placement puts a scanned sheet's mesh tight around it") {
    // A horizontal sheet of points: a layer of cells with 40 points each at k = 5 in a 12^3
    // grid of unit cells (layer centre z = 5.5). The plain level set at iso 4 wraps it at
    // z = 5.5 +- 0.89; surface placement puts both faces on the layer's cell faces, +- 0.5.
    auto sheet = [](std::uint64_t below, std::uint64_t at) {
        test::DenseCells g;
        g.spec.dims = {12, 12, 12};
        g.count.assign(g.spec.cell_count(), 0);
        for (std::uint64_t c = 0; c < 144; ++c) g.count[4 * 144 + c] = below, g.count[5 * 144 + c] = at;
        return g;
    };
    auto z_range = [](const Mesh& m) {
        float lo = 1e9f, hi = -1e9f;
        for (const auto& p : m.positions)
            if (p[0] > 2 && p[0] < 10 && p[1] > 2 && p[1] < 10) lo = std::min(lo, p[2]), hi = std::max(hi, p[2]);
        return std::pair{lo, hi};
    };
    const auto [iso_lo, iso_hi] = z_range(extract_closed_surface(sheet(0, 40), 4, VertexPlacement::iso));
    CHECK(iso_lo == doctest::Approx(5.5 - (40 - 4.5) / 40.0));
    CHECK(iso_hi == doctest::Approx(5.5 + (40 - 4.5) / 40.0));
    const auto [lo, hi] = z_range(extract_closed_surface(sheet(0, 40), 4));
    CHECK(lo == doctest::Approx(5.0));
    CHECK(hi == doctest::Approx(6.0));
    // Spread evenly over two layers (the sheet on their shared face, z = 5): each face moves in
    // towards its layer's centre, as far as a tenth of an edge from it.
    const auto [lo2, hi2] = z_range(extract_closed_surface(sheet(20, 20), 4));
    CHECK(lo2 == doctest::Approx(4.5 - 0.1));
    CHECK(hi2 == doctest::Approx(5.5 + 0.1));
    CHECK(parse_placement("iso") == VertexPlacement::iso);
    CHECK_THROWS_AS(parse_placement("middle"), Error);
}

TEST_CASE("vertex colours weigh each cell's mean colour by its count") {
    // Two adjacent cells: 30 red points and 10 blue ones; the surface crosses between them and
    // the padding. A single-colour shape keeps its exact colour.
    test::DenseCells g;
    g.spec.dims = {2, 1, 1};
    g.count = {30, 10};
    g.red = {30 * 255, 0};
    g.green = {0, 0};
    g.blue = {0, 10 * 255};
    g.color_max_word = 255;
    const Mesh m = extract_closed_surface(g, 4.5, VertexPlacement::iso);
    REQUIRE(m.colors.size() == m.positions.size());
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const float x = m.positions[v][0];
        if (x < 0.5f) CHECK(m.colors[v] == std::array<std::uint8_t, 3>{255, 0, 0}); // between padding and red
        if (x > 1.5f) CHECK(m.colors[v] == std::array<std::uint8_t, 3>{0, 0, 255}); // between blue and padding
    }
    CHECK(parse_iso("auto") < 0);
    CHECK(parse_iso("2.5") == 2.5);
}

TEST_CASE("random inside/outside patterns: neighbouring cubes always agree") {
    // Arbitrary binary fields exercise every pairing of cases across shared faces.
    std::uint64_t state = 12345;
    auto next = [&] { return (state = state * 6364136223846793005ull + 1442695040888963407ull) >> 33; };
    for (int trial = 0; trial < 20000; ++trial) {
        test::DenseCells g;
        g.spec.dims = {3, 3, 3};
        g.count.resize(27);
        for (auto& c : g.count) c = next() % 2 ? 10 : 0;
        CAPTURE(trial);
        const Topology t = topology(extract_closed_surface(g, 5));
        REQUIRE(t.closed);
        REQUIRE(t.oriented);
    }
}
