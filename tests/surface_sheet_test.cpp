// SPDX-License-Identifier: Apache-2.0
// One sheet per scanned surface: placed on the points (below the cell), one sheet for a thin
// plate scanned from both sides, closed and consistently oriented where the surface is closed,
// and the same mesh for any number of threads.
#include "build_steps.hpp"
#include "grid/thin_parts.hpp"
#include "mesh/marching_cubes.hpp"
#include "mesh/mesh_edit.hpp"
#include "mesh/surface_sheet.hpp"
#include "mesh/tiled_sheet.hpp"

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <map>
#include <numbers>
#include <utility>

using namespace lasmesh;

namespace {

// The next number of a 64-bit linear congruential sequence, uniform in [0, 1).
double uniform(std::uint64_t& state) {
    return double((state = state * 6364136223846793005ull + 1442695040888963407ull) >> 11) / double(1ull << 53);
}

lasgen::GeneratedPoint point(double x, double y, double z) {
    lasgen::GeneratedPoint p;
    p.position = {x, y, z};
    p.color = {90, 140, 200};
    return p;
}

struct EdgeUse {
    int forward = 0, backward = 0;
};

// Every edge's uses: a closed oriented surface uses each edge once in each direction; an open
// sheet also has boundary edges used once.
std::map<std::pair<std::uint32_t, std::uint32_t>, EdgeUse> edge_uses(const Mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, EdgeUse> uses;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            if (a < b)
                ++uses[{a, b}].forward;
            else
                ++uses[{b, a}].backward;
        }
    return uses;
}

double triangle_area(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const auto& a = m.positions[t[0]];
    const auto& b = m.positions[t[1]];
    const auto& c = m.positions[t[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

// A floor of 4 x 4 m (one face), a 3 cm plate standing on it at x = 2 (faces at 1.985 and 2.015,
// 3 x 1.8 m) and a rail of 2.5 cm radius at x = 1, z = 1 along y, all with 1 cm of noise (as
// lasgen's, bounded at 3.46 sigma), about 40 points a face per cell, accumulated at 64 cells.
// The points in a grid of 64 cells along the longest axis, or (`fine`) of half that cell on the
// same origin: the thin parts' grid.
CellGrid grid_of(const std::vector<lasgen::GeneratedPoint>& points, const std::array<double, 3>& min,
                 const std::array<double, 3>& max, bool fine) {
    test::TempDir dir;
    test::write_file(dir.file("points.las"), test::las_with_points(points, min, max, 8, 3, 0.001));
    AccumulateOptions grid;
    grid.grid = GridRequest::longest(64);
    CellGrid g = test::accumulate_file(dir.file("points.las"), grid);
    if (!fine) return g;
    grid.spec = g.spec;
    grid.spec->cell_size /= 2;
    for (std::uint32_t& d : grid.spec->dims) d *= 2;
    return test::accumulate_file(dir.file("points.las"), grid);
}

CellGrid floor_plate_rail() {
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 17;
    auto next = [&] { return uniform(state); };
    auto noise = [&] { return (next() + next() + next() + next() - 2.0) * 1.7320508075688772 * 0.01; };
    for (int i = 0; i < 160000; ++i) points.push_back(point(4 * next(), 4 * next(), noise()));
    for (int i = 0; i < 108000; ++i) {
        const double face = i % 2 ? 2.015 : 1.985;
        points.push_back(point(face + noise(), 0.5 + 3 * next(), 1.8 * next()));
    }
    for (int i = 0; i < 12000; ++i) {
        const double t = 2 * std::numbers::pi * next();
        points.push_back(point(1 + 0.025 * std::cos(t) + noise(), 0.5 + 3 * next(), 1 + 0.025 * std::sin(t) + noise()));
    }
    return grid_of(points, {-0.05, -0.05, -0.05}, {4.05, 4.05, 1.85}, false);
}

// A floor of 4 x 4 m with a post 5 cm across standing on it at x = 1 m (the 16th cell of 6.4 cm,
// on the border of tiles of 16 cells), y = 2 m, 1.2 m tall.
CellGrid floor_post(bool fine) {
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 29;
    auto next = [&] { return uniform(state); };
    auto noise = [&] { return (next() + next() + next() + next() - 2.0) * 1.7320508075688772 * 0.005; };
    for (int i = 0; i < 160000; ++i) points.push_back(point(4 * next(), 4 * next(), noise()));
    for (int i = 0; i < 20000; ++i) {
        const double t = 2 * std::numbers::pi * next();
        points.push_back(point(1 + 0.025 * std::cos(t) + noise(), 2 + 0.025 * std::sin(t) + noise(), 1.2 * next()));
    }
    return grid_of(points, {-0.05, -0.05, -0.05}, {4.05, 4.05, 1.25}, fine);
}

// The bricks of `grid` that hold cells x0 <= x < x1, all of y and z.
CellGrid part_in_x(const CellGrid& grid, std::int64_t x0, std::int64_t x1) {
    return bricks_within(grid, x0, x1, 0, std::int64_t{grid.spec.dims[1]});
}

// The triangles whose centroid lies at x0 <= x < x1 (from the mesh's origin), each as its
// corners' positions from its lowest corner on, in its winding; sorted.
std::vector<std::array<float, 9>> triangles_in_x(const Mesh& m, double x0, double x1) {
    std::vector<std::array<float, 9>> kept;
    for (const auto& t : m.triangles) {
        const double x = (m.positions[t[0]][0] + m.positions[t[1]][0] + m.positions[t[2]][0]) / 3;
        if (x < x0 || x >= x1) continue;
        int first = 0;
        for (int k = 1; k < 3; ++k)
            if (m.positions[t[k]] < m.positions[t[first]]) first = k;
        std::array<float, 9> corners{};
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) corners[3 * k + a] = m.positions[t[(first + k) % 3]][a];
        kept.push_back(corners);
    }
    std::sort(kept.begin(), kept.end());
    return kept;
}

// How many triangles one of the two has and the other not.
std::size_t count_differing(const std::vector<std::array<float, 9>>& a, const std::vector<std::array<float, 9>>& b) {
    std::vector<std::array<float, 9>> differ;
    std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(differ));
    return differ.size();
}

// A box of 4 x 2 x 1.5 m on an 8 x 4 m deck, scanned under too (the floor inside it), its edges
// not scanned (a gap of two cells), so that each wall and its roof is a piece of its own: only
// the whole grid's outside (the box's inside enclosed) turns its walls to face out. Cells of
// 12.5 cm (64 along x).
CellGrid box_on_deck() {
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 23;
    auto next = [&] { return uniform(state); };
    for (int i = 0; i < 120000; ++i) points.push_back(point(8 * next(), 4 * next(), 0));
    const double x0 = 2, x1 = 6, y0 = 1, y1 = 3, top = 1.5;
    for (int i = 0; i < 100000; ++i) {
        const double u = next(), v = next();
        const double along = i % 5 < 3 ? u * (x1 - x0) : u * (y1 - y0), length = i % 5 < 3 ? x1 - x0 : y1 - y0;
        const double up = i % 5 == 0 ? std::min(v, 1 - v) * (y1 - y0) : std::min(v, 1 - v) * top;
        if (std::min({along, length - along, up}) < 0.25) continue; // the edges unscanned
        switch (i % 5) {
        case 0: points.push_back(point(x0 + u * (x1 - x0), y0 + v * (y1 - y0), top)); break;
        case 1: points.push_back(point(x0 + u * (x1 - x0), y0, v * top)); break;
        case 2: points.push_back(point(x0 + u * (x1 - x0), y1, v * top)); break;
        case 3: points.push_back(point(x0, y0 + u * (y1 - y0), v * top)); break;
        default: points.push_back(point(x1, y0 + u * (y1 - y0), v * top)); break;
        }
    }
    test::TempDir dir;
    test::write_file(dir.file("box.las"), test::las_with_points(points, {0, 0, 0}, {8, 4, 1.5}, 8, 3, 0.001));
    AccumulateOptions options;
    options.grid = GridRequest::longest(64);
    return test::accumulate_file(dir.file("box.las"), options);
}

} // namespace

TEST_CASE("a sphere's scan gives one closed, oriented sheet on the points, half the closed mesh") {
    test::TempDir dir;
    lasgen::SceneOptions options;
    options.kind = lasgen::SceneKind::sphere;
    options.origin = {0, 0, 0};
    const lasgen::Scene sphere = lasgen::make_scene(options); // 10 m diameter, points on the surface
    test::write_file(dir.file("s.las"), test::make_las(lasgen::LasLayout{}, sphere, 300000, 7));
    AccumulateOptions grid;
    grid.grid = GridRequest::longest(48);
    const CellGrid g = test::accumulate_file(dir.file("s.las"), grid);
    const double iso = automatic_iso(g);
    const Mesh sheet = extract_sheet(g, iso);
    const Mesh closed = extract_closed_surface(g, iso);
    REQUIRE(!sheet.triangles.empty());
    REQUIRE(sheet.normals.size() == sheet.positions.size());
    REQUIRE(sheet.colors.size() == sheet.positions.size());

    // Oriented and nearly closed: every edge at most once each way, and few edges on a
    // boundary (where the band of defined corners is thinner than the cubes the surface
    // crosses, a cube stays empty: see docs/design.md, "Limits").
    std::size_t edges = 0, boundary = 0;
    for (const auto& [edge, use] : edge_uses(sheet)) {
        REQUIRE(use.forward <= 1);
        REQUIRE(use.backward <= 1);
        ++edges;
        boundary += use.forward + use.backward == 1;
    }
    CAPTURE(boundary);
    CHECK(boundary < edges / 50);
    // On the points: the sphere's centre is at the middle of the header bounds, which the grid
    // centres.
    const double h = g.spec.cell_size;
    Vec3 centre{};
    for (int a = 0; a < 3; ++a) centre[a] = g.spec.origin[a] + g.spec.dims[a] * h / 2;
    double total = 0, worst = 0;
    for (const auto& p : sheet.positions) {
        const double d = std::abs(std::hypot(sheet.origin[0] + p[0] - centre[0], sheet.origin[1] + p[1] - centre[1],
                                             sheet.origin[2] + p[2] - centre[2]) -
                                  5.0);
        total += d;
        worst = std::max(worst, d);
    }
    const double mean = total / static_cast<double>(sheet.positions.size());
    CAPTURE(mean / h);
    CAPTURE(worst / h);
    CHECK(mean < 0.05 * h); // the closed surface sits about half a cell off
    CHECK(worst < 0.25 * h);
    // Outward, every normal: a sphere has no "up" to go by.
    std::size_t inward = 0;
    for (std::size_t v = 0; v < sheet.positions.size(); ++v) {
        double along = 0;
        for (int a = 0; a < 3; ++a)
            along += (sheet.origin[a] + sheet.positions[v][a] - centre[a]) * sheet.normals[v][a];
        inward += along <= 0;
    }
    CHECK(inward == 0);
    // Normals agree with the winding: each triangle's face normal and its vertices' normals.
    for (const auto& t : sheet.triangles) {
        const auto& a = sheet.positions[t[0]];
        const auto& b = sheet.positions[t[1]];
        const auto& c = sheet.positions[t[2]];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        const auto& vn = sheet.normals[t[0]];
        REQUIRE(n[0] * vn[0] + n[1] * vn[1] + n[2] * vn[2] > 0);
        REQUIRE(triangle_area(sheet, t) > 0);
    }
    CHECK(sheet.triangles.size() < 0.6 * static_cast<double>(closed.triangles.size()));
}

TEST_CASE("a thin plate scanned from both sides is one sheet between its faces") {
    test::TempDir dir;
    // A 2 cm plate at z = 0.30 m, 10 x 10 m, scanned on both faces (z = 0.29 and 0.31); cells of
    // 0.53 m, so the plate lies inside one layer of cells.
    std::vector<lasgen::GeneratedPoint> points;
    for (int i = 0; i < 200; ++i)
        for (int j = 0; j < 200; ++j) {
            const double x = 0.025 + i * 0.05, y = 0.025 + j * 0.05;
            points.push_back(point(x, y, (i + j) % 2 ? 0.29 : 0.31));
        }
    test::write_file(dir.file("plate.las"), test::las_with_points(points, {0, 0, 0}, {10, 10, 1}));
    AccumulateOptions grid;
    grid.grid = GridRequest::longest(20);
    const CellGrid g = test::accumulate_file(dir.file("plate.las"), grid);
    const Mesh sheet = extract_sheet(g, automatic_iso(g));
    REQUIRE(!sheet.triangles.empty());
    double area = 0;
    for (const auto& t : sheet.triangles) area += triangle_area(sheet, t);
    // One sheet: the plate's area (and the open border up to half a cell beyond its edges), not twice.
    const double h = g.spec.cell_size;
    CHECK(area > 95);
    CHECK(area < (10 + h) * (10 + h) * 1.02);
    for (const auto& p : sheet.positions) REQUIRE(std::abs(sheet.origin[2] + p[2] - 0.3) < 0.0101); // between the faces
    for (const auto& n : sheet.normals) REQUIRE(n[2] > 0.99);                                       // facing up
    int boundary = 0;
    for (const auto& [edge, use] : edge_uses(sheet)) {
        REQUIRE(use.forward + use.backward <= 2);
        REQUIRE(use.forward <= 1);
        REQUIRE(use.backward <= 1);
        boundary += use.forward + use.backward == 1;
    }
    CHECK(boundary > 0); // an open sheet: its rim is a boundary
}

TEST_CASE("a plate thinner than a cell, scanned on both faces with noise, gives two sheets on its faces") {
    // A floor of 4 x 4 m (one face) and a 3 cm plate standing on it at x = 2 (faces at 1.985 and
    // 2.015, 3 x 1.8 m), 1 cm of noise (lasgen's, bounded at 3.46 sigma), about 40 points a face
    // per 6.25 cm cell: the plate's points fill one band of cells, whose middle the sheet follows;
    // the layers' spread (3.25 cm^2 against the floor's 1) tells its two faces.
    // A rail of 2.5 cm radius at x = 1, z = 1 along y, scanned all round: a line of cells, whose
    // points spread across the sheet by the rail's width (3 cm^2 beside the noise's 1), not by
    // two faces.
    const CellGrid g = floor_plate_rail();
    REQUIRE(g.moments_exact());
    const Mesh sheet = extract_sheet(g, automatic_iso(g));
    REQUIRE(sheet.normals.size() == sheet.positions.size());
    // The plate's vertices away from the floor and its rim, by the way they face.
    std::size_t facing_plus = 0, facing_minus = 0, floor = 0, floor_up = 0, floor_down = 0;
    double off_plus = 0, off_minus = 0;
    std::vector<std::array<float, 3>> rail_normals;
    for (std::size_t v = 0; v < sheet.positions.size(); ++v) {
        const double x = sheet.origin[0] + sheet.positions[v][0], y = sheet.origin[1] + sheet.positions[v][1],
                     z = sheet.origin[2] + sheet.positions[v][2];
        const auto& n = sheet.normals[v];
        if (std::abs(x - 2) < 0.1 && z > 0.3 && z < 1.5 && y > 0.8 && y < 3.2) {
            if (n[0] > 0.9) ++facing_plus, off_plus += std::abs(x - 2.015);
            if (n[0] < -0.9) ++facing_minus, off_minus += std::abs(x - 1.985);
        }
        if (std::abs(x - 2) > 0.4 && z < 0.1) ++floor, floor_up += n[2] > 0.9, floor_down += n[2] < -0.9;
        if (std::abs(x - 1) < 0.15 && std::abs(z - 1) < 0.15 && y > 0.8 && y < 3.2) rail_normals.push_back(n);
    }
    // The rail is one sheet: its normals agree with their mean (two sheets back to back would
    // give half of them against it; one ribbon round the rail a tenth).
    REQUIRE(rail_normals.size() > 20);
    std::array<double, 3> mean{};
    for (const auto& n : rail_normals)
        for (int a = 0; a < 3; ++a) mean[a] += n[a];
    std::size_t against = 0;
    for (const auto& n : rail_normals) against += n[0] * mean[0] + n[1] * mean[1] + n[2] * mean[2] < 0;
    CAPTURE(rail_normals.size());
    CHECK(against * 4 < rail_normals.size());
    CAPTURE(facing_plus);
    CAPTURE(facing_minus);
    REQUIRE(facing_plus > 300);
    REQUIRE(facing_minus > 300);
    // Each face on its face: a sheet between them would be 1.5 cm off.
    CHECK(off_plus / double(facing_plus) < 0.004);
    CHECK(off_minus / double(facing_minus) < 0.004);
    // The floor, scanned from one side with the same noise, stays one sheet: all its vertices face
    // one way (its side is the orientation's business, not tested here).
    REQUIRE(floor > 1000);
    CHECK(std::max(floor_up, floor_down) == floor);
}

TEST_CASE("a noisy plane across cell faces: the sheet on the plane, not on the halves the faces cut") {
    // A plane rising 5 cm a metre over 3 x 3 m, 1 cm of noise (as lasgen's, bounded at 3.46
    // sigma), about 60 points a cell of 6 cm: the plane crosses the horizontal cell faces at every
    // height, and where it runs near one each cell holds a tail of the noise, whose centroid lies
    // up to 0.8 cm off the plane. The sheet's vertices must lie on the plane, well inside that.
    test::TempDir dir;
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 11;
    const auto noise = [&] {
        return (uniform(state) + uniform(state) + uniform(state) + uniform(state) - 2.0) * 1.7320508075688772 * 0.01;
    };
    for (int k = 0; k < 150000; ++k) {
        const double x = 3 * uniform(state), y = 3 * uniform(state);
        points.push_back(point(x + noise(), y + noise(), 0.5 + 0.05 * x + noise()));
    }
    test::write_file(dir.file("plane.las"),
                     test::las_with_points(points, {-0.05, -0.05, 0.4}, {3.05, 3.05, 0.75}, 8, 3, 0.001));
    AccumulateOptions grid;
    grid.grid = GridRequest::longest(52); // cells of 6 cm
    const CellGrid g = test::accumulate_file(dir.file("plane.las"), grid);
    const Mesh sheet = extract_sheet(g, automatic_iso(g));
    REQUIRE(sheet.positions.size() > 1000);
    // The distance of each vertex away from the sheet's rim from the plane, along its normal.
    const double h = g.spec.cell_size, norm = std::sqrt(1 + 0.05 * 0.05);
    double sum = 0;
    std::size_t inside = 0;
    for (const auto& p : sheet.positions) {
        const double x = sheet.origin[0] + p[0], y = sheet.origin[1] + p[1], z = sheet.origin[2] + p[2];
        if (x < 2 * h || x > 3 - 2 * h || y < 2 * h || y > 3 - 2 * h) continue;
        sum += std::abs(z - 0.5 - 0.05 * x) / norm;
        ++inside;
    }
    REQUIRE(inside > 1000);
    CAPTURE(sum / double(inside));
    CHECK(sum / double(inside) < 0.0035); // 0.26 cm; the cells' tails alone: 0.76 cm

    // A pipe of 25 cm radius along y, the same noise and cells: pooled with the cells along its
    // surface as well as across it, the sheet would sink toward the axis by the arc's sagitta.
    points.clear();
    for (int k = 0; k < 150000; ++k) {
        const double t = 2 * std::numbers::pi * uniform(state), y = 3 * uniform(state);
        points.push_back(point(1.5 + 0.25 * std::cos(t) + noise(), y + noise(), 1.5 + 0.25 * std::sin(t) + noise()));
    }
    test::write_file(dir.file("pipe.las"),
                     test::las_with_points(points, {1.2, -0.05, 1.2}, {1.8, 3.05, 1.8}, 8, 3, 0.001));
    const CellGrid pipe_grid = test::accumulate_file(dir.file("pipe.las"), grid);
    const Mesh pipe = extract_sheet(pipe_grid, automatic_iso(pipe_grid));
    double signed_sum = 0;
    inside = 0;
    for (const auto& p : pipe.positions) {
        const double x = pipe.origin[0] + p[0], y = pipe.origin[1] + p[1], z = pipe.origin[2] + p[2];
        if (y < 2 * h || y > 3 - 2 * h) continue;
        signed_sum += std::hypot(x - 1.5, z - 1.5) - 0.25;
        ++inside;
    }
    REQUIRE(inside > 500);
    CAPTURE(signed_sum / double(inside));
    CHECK(std::abs(signed_sum / double(inside)) < 0.003); // 0.13 cm; pooled along it too: 0.66 cm
}

TEST_CASE("a sheet ends where its points do, not a cell on; a steep plane keeps no hole") {
    // A plate at z = 0.5 over x 0-1.99, y 0-3, 1 cm of noise on each axis, cells of 6 cm: its edge lies part
    // of the way into a column of cells. The sheet runs to the edge and ends at that column's far
    // side, 0.96 cells past the points (left to run a cell on into the next column, it ended 2.0
    // cells out; cut back at every corner past the points, 0.2 cells short of them).
    test::TempDir dir;
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 5;
    const auto noise = [&] {
        return (uniform(state) + uniform(state) + uniform(state) + uniform(state) - 2.0) * 1.7320508075688772 * 0.01;
    };
    for (int k = 0; k < 100000; ++k) {
        const double x = 1.99 * uniform(state), y = 3 * uniform(state);
        points.push_back(point(x + noise(), y + noise(), 0.5 + noise()));
    }
    test::write_file(dir.file("plate.las"),
                     test::las_with_points(points, {-0.05, -0.05, 0.4}, {3.05, 3.05, 0.75}, 8, 3, 0.001));
    AccumulateOptions grid;
    grid.grid = GridRequest::longest(52); // cells of 5.96 cm
    const CellGrid g = test::accumulate_file(dir.file("plate.las"), grid);
    const double h = g.spec.cell_size;
    const Mesh sheet = extract_sheet(g, automatic_iso(g));
    double x_max = -1;
    for (const auto& p : sheet.positions) x_max = std::max(x_max, sheet.origin[0] + p[0]);
    CAPTURE(x_max);
    CHECK(x_max > 1.99 + 0.5 * h); // to that column's far side, not cut back before it
    CHECK(x_max < 1.99 + 1.2 * h);

    // A plane at 35 degrees across the lattice, cut to a disc: the zero set leaves surface cells
    // into empty ones and returns all over it, and inside the disc there is no border edge.
    points.clear();
    const double slope = std::tan(35 * std::numbers::pi / 180);
    for (int k = 0; k < 200000; ++k) {
        const double r = 1.2 * std::sqrt(uniform(state)), t = 2 * std::numbers::pi * uniform(state);
        const double x = 1.5 + r * std::cos(t), y = 1.5 + r * std::sin(t);
        points.push_back(point(x + noise(), y + noise(), 0.5 + slope * (x - 1.5) + noise()));
    }
    test::write_file(dir.file("slope.las"),
                     test::las_with_points(points, {-0.05, -0.05, -0.5}, {3.05, 3.05, 1.6}, 8, 3, 0.001));
    const CellGrid slope_grid = test::accumulate_file(dir.file("slope.las"), grid);
    const Mesh slanted = extract_sheet(slope_grid, automatic_iso(slope_grid));
    std::size_t border_inside = 0, border = 0;
    for (const auto& [edge, use] : edge_uses(slanted)) {
        if (use.forward + use.backward != 1) continue;
        ++border;
        const auto& a = slanted.positions[edge.first];
        const double x = slanted.origin[0] + a[0] - 1.5, y = slanted.origin[1] + a[1] - 1.5;
        border_inside += std::hypot(x, y) < 1.0;
    }
    CHECK(border > 100); // the disc's rim
    CHECK(border_inside == 0);
}

TEST_CASE("the sheet is the same for any number of threads") {
    test::TempDir dir;
    lasgen::SceneOptions options;
    options.origin = {0, 0, 0};
    const lasgen::Scene deck = lasgen::make_scene(options);
    test::write_file(dir.file("d.las"), test::make_las(lasgen::LasLayout{}, deck, 200000, 11));
    AccumulateOptions grid;
    grid.grid = GridRequest::longest(128);
    const CellGrid g = test::accumulate_file(dir.file("d.las"), grid);
    auto extract = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return extract_sheet(g, automatic_iso(g));
    };
    const Mesh one = extract(1), two = extract(2);
    REQUIRE(!one.triangles.empty());
    CHECK(one.positions == two.positions);
    CHECK(one.normals == two.normals);
    CHECK(one.colors == two.colors);
    CHECK(one.triangles == two.triangles);
}

TEST_CASE("boxes on a deck face outward, their walls too, whichever way their neighbours face") {
    // Two boxes 1.5 m apart on a 20 x 12 m deck: a wall's inside is enclosed, its outside open,
    // and the wall facing the other box too. Not scanned under the boxes, as no scanner sees it;
    // or scanned there too, as some generated decks are, where the floor inside a box would turn
    // its walls inward if the outside did not say otherwise (at the coarser grid: at 320 cells
    // the spanning tree still reaches some walls from inside). Or with the boxes' edges unscanned
    // (a gap of a cell or two, as occlusion leaves them): each wall is then a flat piece of its
    // own, which only the enclosed space behind it can turn outward.
    bool scanned_under = false;
    double edge_gap = 0;
    std::vector<const char*> grids{"160", "320"};
    SUBCASE("not scanned under the boxes") {}
    SUBCASE("scanned under the boxes") {
        scanned_under = true, grids = {"160"};
    }
    SUBCASE("edges unscanned") {
        edge_gap = 0.1, grids = {"160"};
    }
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 11;
    auto next = [&] { return uniform(state); };
    struct Box {
        double x0, y0, x1, y1, top;
    };
    const std::vector<Box> boxes{{4, 3, 10, 5.5, 2.6}, {4, 7, 10, 9.5, 2.6}};
    while (points.size() < 200000) {
        const double x = 20 * next(), y = 12 * next();
        bool under = false;
        for (const Box& b : boxes) under = under || (x > b.x0 && x < b.x1 && y > b.y0 && y < b.y1);
        if (!under || scanned_under) points.push_back(point(x, y, 0));
    }
    for (const Box& b : boxes)
        for (int i = 0; i < 60000; ++i) {
            const double u = next(), v = next();
            const double along = i % 5 < 3 ? u * (b.x1 - b.x0) : u * (b.y1 - b.y0),
                         length = i % 5 < 3 ? b.x1 - b.x0 : b.y1 - b.y0;
            const double up = i % 5 == 0 ? std::min(v * (b.y1 - b.y0), (1 - v) * (b.y1 - b.y0))
                                         : std::min(v * b.top, (1 - v) * b.top);
            if (std::min({along, length - along, up}) < edge_gap) continue;
            switch (i % 5) {
            case 0: points.push_back(point(b.x0 + u * (b.x1 - b.x0), b.y0 + v * (b.y1 - b.y0), b.top)); break;
            case 1: points.push_back(point(b.x0 + u * (b.x1 - b.x0), b.y0, v * b.top)); break;
            case 2: points.push_back(point(b.x0 + u * (b.x1 - b.x0), b.y1, v * b.top)); break;
            case 3: points.push_back(point(b.x0, b.y0 + u * (b.y1 - b.y0), v * b.top)); break;
            default: points.push_back(point(b.x1, b.y0 + u * (b.y1 - b.y0), v * b.top)); break;
            }
        }
    test::TempDir dir;
    test::write_file(dir.file("boxes.las"), test::las_with_points(points, {0, 0, 0}, {20, 12, 2.6}, 8, 3, 0.001));
    for (const char* cells : grids) {
        CAPTURE(cells);
        AccumulateOptions grid;
        grid.grid = GridRequest::longest(static_cast<std::uint32_t>(std::stoi(cells)));
        const CellGrid g = test::accumulate_file(dir.file("boxes.las"), grid);
        const Mesh sheet = extract_sheet(g, automatic_iso(g));
        REQUIRE(sheet.normals.size() == sheet.positions.size());
        std::size_t walls = 0, wrong_walls = 0, roofs = 0, wrong_roofs = 0, deck = 0, wrong_deck = 0;
        for (std::size_t v = 0; v < sheet.positions.size(); ++v) {
            const double x = sheet.origin[0] + sheet.positions[v][0], y = sheet.origin[1] + sheet.positions[v][1],
                         z = sheet.origin[2] + sheet.positions[v][2];
            const auto& n = sheet.normals[v];
            bool near_box = false;
            for (const Box& b : boxes) {
                if (x < b.x0 - 0.3 || x > b.x1 + 0.3 || y < b.y0 - 0.3 || y > b.y1 + 0.3) continue;
                near_box = true;
                const double cx = (b.x0 + b.x1) / 2, cy = (b.y0 + b.y1) / 2;
                const bool inner = x > b.x0 + 0.2 && x < b.x1 - 0.2 && y > b.y0 + 0.2 && y < b.y1 - 0.2;
                if (z > b.top - 0.2 && inner)
                    ++roofs, wrong_roofs += n[2] <= 0;
                else if (z > 0.5 && z < b.top - 0.2 && !inner)
                    ++walls, wrong_walls += (x - cx) * n[0] + (y - cy) * n[1] <= 0;
            }
            if (!near_box && z < 0.2 && x > 0.3 && x < 19.7 && y > 0.3 && y < 11.7)
                ++deck, wrong_deck += n[2] <= 0; // off its border
        }
        CAPTURE(walls);
        CAPTURE(roofs);
        CAPTURE(deck);
        CHECK(walls > 100);
        CHECK(wrong_walls <= walls / 100);
        CHECK(wrong_roofs <= roofs / 100);
        CHECK(wrong_deck == 0);
    }
}

TEST_CASE("a torus faces outward: its inside is enclosed, though its normals do not point away from its centre") {
    // Normals away from the centroid agree with only a quarter of a torus's area-weighted surface
    // (R = 2, r = 0.6), and it has no up: only the enclosed space inside the tube tells its sides.
    const double big = 2, small = 0.6;
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 5;
    auto next = [&] { return uniform(state); };
    while (points.size() < 150000) {
        const double u = 2 * std::numbers::pi * next(), t = 2 * std::numbers::pi * next();
        if (next() * (big + small) > big + small * std::cos(t)) continue; // uniform by area
        const double rho = big + small * std::cos(t);
        points.push_back(point(4 + rho * std::cos(u), 4 + rho * std::sin(u), 1 + small * std::sin(t)));
    }
    test::TempDir dir;
    test::write_file(dir.file("torus.las"),
                     test::las_with_points(points, {1.4, 1.4, 0.4}, {6.6, 6.6, 1.6}, 8, 3, 0.001));
    AccumulateOptions grid;
    grid.grid = GridRequest::longest(96);
    const CellGrid g = test::accumulate_file(dir.file("torus.las"), grid);
    const Mesh sheet = extract_sheet(g, automatic_iso(g));
    REQUIRE(sheet.normals.size() == sheet.positions.size());
    REQUIRE(sheet.positions.size() > 1000);
    std::size_t inward = 0;
    for (std::size_t v = 0; v < sheet.positions.size(); ++v) {
        const double x = sheet.origin[0] + sheet.positions[v][0] - 4, y = sheet.origin[1] + sheet.positions[v][1] - 4,
                     z = sheet.origin[2] + sheet.positions[v][2] - 1;
        const double rho = std::hypot(x, y);
        // From the nearest point of the tube's core circle to the vertex: outward.
        const double away[3] = {x - big * x / rho, y - big * y / rho, z};
        const auto& n = sheet.normals[v];
        inward += away[0] * n[0] + away[1] * n[1] + away[2] * n[2] <= 0;
    }
    CAPTURE(sheet.positions.size());
    CHECK(inward == 0);
}

TEST_CASE("thin parts at a fine grid: a rail is a tube of its own radius, one thinner than the lattice holds is kept") {
    // Two rails along x (slightly tilted off the lattice), of radius 2.5 cm and 0.8 cm, 1 m long,
    // meshed at cells of 3 cm: the first is a few cells across, the second slips between the
    // lattice's corners (under half a cell's diagonal, 2.1 cm). Measured away from their ends.
    const double cell = 0.03, length = 1, from = 0.1 + 3 * cell, to = 0.1 + length - 3 * cell;
    const std::array<double, 2> radii{0.025, 0.008};
    const auto axis_at = [&](int rail, double x) { // the axis's y and z at x
        return std::array<double, 2>{0.2 + 0.3 * rail + 0.03 * x, 0.2 + 0.02 * x};
    };
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 11;
    auto next = [&] { return uniform(state); };
    for (int rail = 0; rail < 2; ++rail)
        for (int i = 0; i < 60000; ++i) {
            const double x = 0.1 + length * next(), angle = 2 * std::numbers::pi * next();
            const auto at = axis_at(rail, x);
            points.push_back(point(x, at[0] + radii[rail] * std::cos(angle), at[1] + radii[rail] * std::sin(angle)));
        }
    test::TempDir dir;
    test::write_file(dir.file("rails.las"), test::las_with_points(points, {0, 0, 0}, {1.2, 0.8, 0.4}, 8, 3, 0.0001));
    AccumulateOptions grid;
    grid.grid = GridRequest::cell_edge(cell);
    const CellGrid g = test::accumulate_file(dir.file("rails.las"), grid);
    struct Fit {
        std::array<double, 2> off{}, span{}; // per rail: mean |distance from the axis - radius|, length covered
        std::size_t border = 0;              // border edges
    };
    const auto fit = [&](const Mesh& m) {
        Fit f;
        for (int rail = 0; rail < 2; ++rail) {
            const double expected = std::max(radii[rail], std::numbers::sqrt2 / 2 * g.spec.cell_size);
            double off = 0, first = 1e9, last = -1e9;
            std::size_t count = 0;
            for (const auto& p : m.positions) {
                const double x = m.origin[0] + p[0], y = m.origin[1] + p[1], z = m.origin[2] + p[2];
                const auto at = axis_at(rail, x);
                const double d = std::hypot(y - at[0], z - at[1]);
                if (d > 0.1 || x < from || x > to) continue;
                off += std::abs(d - expected), ++count;
                first = std::min(first, x), last = std::max(last, x);
            }
            f.off[rail] = count ? off / double(count) : 1e9;
            f.span[rail] = count ? last - first : 0;
        }
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
        for (const auto& t : m.triangles)
            for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
        for (const auto& [edge, n] : uses) {
            const double x = m.origin[0] + (m.positions[edge.first][0] + m.positions[edge.second][0]) / 2;
            f.border += n == 1 && x > from && x < to;
        }
        return f;
    };
    const Fit tubes = fit(extract_sheet(g, automatic_iso(g), LinearParts::tubes));
    const Fit planes = fit(extract_sheet(g, automatic_iso(g)));
    for (int rail = 0; rail < 2; ++rail) {
        CAPTURE(rail);
        const double expected = std::max(radii[rail], std::numbers::sqrt2 / 2 * g.spec.cell_size);
        CHECK(tubes.off[rail] < 0.2 * expected); // round its axis at its radius, or the lattice's smallest
        CHECK(tubes.span[rail] > 0.75 * length); // its whole length
    }
    // Closer than the planes' sheet of the same cells, and closed round where that is torn.
    CHECK(tubes.off[0] < 0.5 * planes.off[0]);
    CHECK(tubes.border == 0);
    CHECK(planes.border > 50);
}

TEST_CASE("thin parts at a fine grid: a rail crossing a post is closed where they meet") {
    // A rail along x and a post along z, both of radius 2.5 cm, crossing at (0.5, 0.3, 0.5), at
    // cells of 3 cm: the cells where they cross lie along two lines, not one.
    const double cell = 0.03, radius = 0.025;
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 7;
    auto next = [&] { return uniform(state); };
    while (points.size() < 80000) {
        const double s = 0.1 + 0.8 * next(), angle = 2 * std::numbers::pi * next();
        const double u = radius * std::cos(angle), v = radius * std::sin(angle);
        if (points.size() % 2 == 0) { // the rail, less what lies inside the post
            if (std::hypot(s - 0.5, u) > radius) points.push_back(point(s, 0.3 + u, 0.5 + v));
        } else if (std::hypot(u, s - 0.5) > radius) { // the post, less what lies inside the rail
            points.push_back(point(0.5 + u, 0.3 + v, s));
        }
    }
    test::TempDir dir;
    test::write_file(dir.file("cross.las"), test::las_with_points(points, {0, 0, 0}, {1, 0.6, 1}, 8, 3, 0.0001));
    AccumulateOptions grid;
    grid.grid = GridRequest::cell_edge(cell);
    const CellGrid g = test::accumulate_file(dir.file("cross.las"), grid);
    const Mesh tubes = extract_sheet(g, automatic_iso(g), LinearParts::tubes);
    // The border edges within 15 cm of the crossing (the tubes' ends are farther).
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const auto& t : tubes.triangles)
        for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    std::size_t near_crossing = 0, triangles_near = 0;
    const auto near = [&](std::uint32_t v) {
        return std::hypot(tubes.origin[0] + tubes.positions[v][0] - 0.5, tubes.origin[1] + tubes.positions[v][1] - 0.3,
                          tubes.origin[2] + tubes.positions[v][2] - 0.5) < 0.15;
    };
    for (const auto& [edge, n] : uses) near_crossing += n == 1 && near(edge.first) && near(edge.second);
    for (const auto& t : tubes.triangles) triangles_near += near(t[0]);
    CHECK(triangles_near > 50);
    CHECK(near_crossing == 0);
}

TEST_CASE("thin parts at a fine grid: a plane a post stands on stays a plane round its foot") {
    // A post of radius 2.5 cm along z from a floor at z = 0.312, at cells of 3 cm. The floor's
    // cells next to the post lie on its tube's line, but across it: they keep their plane, and the
    // floor stays flat up to the post rather than rising into it as a flare (3.7 cm high when they
    // take the tube; 2 cm when told by their neighbourhood's plane, which leans toward the post).
    const double cell = 0.03, radius = 0.025, floor = 0.312;
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 5;
    auto next = [&] { return uniform(state); };
    // The same points per area on both (about 200 per 10 cm square).
    while (points.size() < 150000) {
        if (points.size() % 8 != 0) {
            const double x = 0.1 + 0.8 * next(), y = 0.1 + 0.8 * next();
            if (std::hypot(x - 0.5, y - 0.5) > radius) points.push_back(point(x, y, floor));
        } else {
            const double z = floor + 0.6 * next(), angle = 2 * std::numbers::pi * next();
            points.push_back(point(0.5 + radius * std::cos(angle), 0.5 + radius * std::sin(angle), z));
        }
    }
    test::TempDir dir;
    test::write_file(dir.file("post.las"), test::las_with_points(points, {0, 0, 0}, {1, 1, 1}, 8, 3, 0.0001));
    AccumulateOptions grid;
    grid.grid = GridRequest::cell_edge(cell);
    const CellGrid g = test::accumulate_file(dir.file("post.las"), grid);
    const Mesh m = extract_sheet(g, automatic_iso(g), LinearParts::tubes);
    // The floor's vertices round the foot (1.5 to 4 cells from the post's surface, below 10 cm).
    double highest = 0;
    std::size_t count = 0;
    for (const auto& p : m.positions) {
        const double x = m.origin[0] + p[0], y = m.origin[1] + p[1], z = m.origin[2] + p[2];
        const double from_axis = std::hypot(x - 0.5, y - 0.5);
        if (from_axis < radius + 1.5 * cell || from_axis > radius + 4 * cell || z > floor + 0.1) continue;
        highest = std::max(highest, std::abs(z - floor)), ++count;
    }
    CHECK(count > 50);
    CHECK(highest < 0.25 * cell);
}

TEST_CASE("thin parts at a fine grid: a noisy plane's edge is no tube") {
    // A plane at z = 0.312 with 1 cm of noise (the sum of three uniforms), ending along x = 0.5, at
    // cells of 3 cm. Along its edge the cells around lie in a strip two or three cells wide and as
    // thick as the noise: long, and flat across, not round. Taken for a tube, the edge became a
    // cylinder of at least half a cell's diagonal round the strip, standing off the plane.
    const double cell = 0.03, level = 0.312;
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 3;
    auto next = [&] { return uniform(state); };
    while (points.size() < 100000) {
        const double x = 0.1 + 0.4 * next(), y = 0.1 + 0.8 * next();
        const double noise = (next() + next() + next() - 1.5) * 0.02;
        points.push_back(point(x, y, level + noise));
    }
    test::TempDir dir;
    test::write_file(dir.file("edge.las"), test::las_with_points(points, {0, 0, 0}, {1, 1, 1}, 8, 3, 0.0001));
    AccumulateOptions grid;
    grid.grid = GridRequest::cell_edge(cell);
    const CellGrid g = test::accumulate_file(dir.file("edge.las"), grid);
    const Mesh m = extract_sheet(g, automatic_iso(g), LinearParts::tubes);
    REQUIRE(!m.triangles.empty());
    double farthest = 0;
    std::size_t near_edge = 0;
    for (const auto& p : m.positions) {
        const double x = m.origin[0] + p[0], y = m.origin[1] + p[1], z = m.origin[2] + p[2];
        if (y < 0.2 || y > 0.8) continue;
        farthest = std::max(farthest, std::abs(z - level));
        near_edge += x > 0.45;
    }
    CHECK(near_edge > 20);
    CHECK(farthest < 0.6 * cell); // 2.6 cm as a tube
}

TEST_CASE("a part of the grid, meshed with the whole grid's noise and outside, is the whole grid's sheet there") {
    // The part: the bricks of the cells 16 to 47 in x (the plate at 31, the rail at the part's
    // edge), all of y and z, in the whole grid's frame. Inside it, 8 cells from its edges in x,
    // the sheets must be the same triangles, facing the same way: the plate's two faces too, whose
    // spread is told against the whole scan's noise (most of the part's layers are the plate's, so
    // its own median would be the plate's spread, and the plate one sheet).
    const CellGrid g = floor_plate_rail();
    const double iso = automatic_iso(g);
    const SheetSurvey survey = sheet_survey(g, iso);
    CHECK(survey.noise > 0.00005); // about (1 cm)^2
    CHECK(survey.noise < 0.0002);
    const CellGrid part = part_in_x(g, 16, 48);
    REQUIRE(part.cells.size() * 4 < g.cells.size() * 3);
    const double x0 = 24 * g.spec.cell_size, x1 = 40 * g.spec.cell_size;
    const std::vector<std::array<float, 9>> expected = triangles_in_x(extract_sheet(g, iso), x0, x1);
    const std::vector<std::array<float, 9>> got = triangles_in_x(extract_sheet(part, iso, survey), x0, x1);
    // Not vacuous: the plate is two faces inside, each of many triangles.
    std::size_t plate_faces = 0;
    for (const auto& c : expected) plate_faces += std::abs(c[0] + g.spec.origin[0] - 2) < 0.03 && c[2] > 0.3;
    CAPTURE(plate_faces);
    CHECK(plate_faces > 1000);
    CAPTURE(expected.size());
    CHECK(count_differing(expected, got) == 0);
}

TEST_CASE("the survey from parts of the grid, each with a halo, is the whole grid's survey") {
    // Six parts of uneven sizes, each from its bricks and 8 cells round them; each hands on its
    // own planes' layers and the outside's voxels its own surface cells are in.
    const CellGrid g = floor_plate_rail();
    const double iso = automatic_iso(g);
    const std::array<std::int64_t, 4> x{0, 20, 44, 64}, y{0, 32, 64, 0};
    std::vector<SurveyPart> parts;
    std::size_t spreads = 0;
    std::vector<std::array<std::int64_t, 3>> walls;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 2; ++j) {
            const CellGrid part = bricks_within(g, x[i] - 8, x[i + 1] + 8, y[j] - 8, y[j + 1] + 8);
            parts.push_back(sheet_survey_part(part, iso, {x[i], x[i + 1], y[j], y[j + 1]}));
            spreads += parts.back().spreads.size();
            walls.insert(walls.end(), parts.back().walls.begin(), parts.back().walls.end());
        }
    const SurveyPart whole = sheet_survey_part(g, iso, {0, 64, 0, 64});
    CHECK(spreads == whole.spreads.size()); // each plane's layer once, by the part it lies in
    CHECK(whole.spreads.size() > 1000);
    std::sort(walls.begin(), walls.end());
    CHECK(walls == whole.walls); // the parts' voxels are disjoint: a voxel is 2^0 cells here
    const SheetSurvey expected = sheet_survey(g, iso), got = combined_survey(parts, g.spec.dims);
    CHECK(expected.noise > 0.00005);
    CHECK(got.noise == expected.noise);
    REQUIRE(got.outside);
    CHECK(*got.outside == *expected.outside);
    // Not vacuous: the outside without one part's walls is another.
    parts[2].walls.clear();
    CHECK_FALSE(*combined_survey(parts, g.spec.dims).outside == *expected.outside);
}

TEST_CASE("a grid meshed tile by tile is the whole grid's sheet, triangle for triangle") {
    // Tiles of 16 and 24 cells with halos of 8. Each tile faces its planes as the whole grid does
    // (plane_facing) and its parts turn as the whole sheet's do (outside_turns).
    const double everywhere = 1e9;
    const auto tiled = [&](const CellGrid& g, std::int64_t tile) {
        return triangles_in_x(extract_sheet_in_tiles(g, automatic_iso(g), tile, 8), -everywhere, everywhere);
    };
    SUBCASE("a plate scanned on both faces, a rail, a floor") {
        // The plate (x = 2 m, the 32nd cell), split into two sheets, lies on a tile border with
        // tiles of 16, inside a tile with 24; the rail and the floor cross many tiles.
        const CellGrid g = floor_plate_rail();
        const std::vector<std::array<float, 9>> whole =
            triangles_in_x(extract_sheet(g, automatic_iso(g)), -everywhere, everywhere);
        std::size_t plate_faces = 0;
        for (const auto& c : whole) plate_faces += std::abs(c[0] + g.spec.origin[0] - 2) < 0.03 && c[2] > 0.3;
        CHECK(plate_faces > 1000);
        for (const std::int64_t tile : {16, 24}) {
            CAPTURE(tile);
            const std::vector<std::array<float, 9>> got = tiled(g, tile);
            CHECK(got.size() == whole.size());
            CHECK(count_differing(whole, got) == 0);
        }
    }
    SUBCASE("a box whose walls turn to face out, across tiles") {
        // Its walls are pieces of their own, turned by the whole sheet's last step (its connected
        // parts facing the outside): the tiles' parts must turn as they do.
        const CellGrid g = box_on_deck();
        const std::vector<std::array<float, 9>> whole =
            triangles_in_x(extract_sheet(g, automatic_iso(g)), -everywhere, everywhere);
        CHECK(whole.size() > 3000);
        for (const std::int64_t tile : {16, 24}) {
            CAPTURE(tile);
            CHECK(count_differing(whole, tiled(g, tile)) == 0);
        }
    }
    SUBCASE("a small deck, some of whose parts the last step turns") {
        // 60,000 points of the generated deck, the automatic grid: the whole sheet's last step
        // turns some of its parts to face the outside (a thousand triangles with tiles of 32
        // when the tiles' parts keep the facing of their planes), parts that run through tiles.
        test::TempDir dir;
        lasgen::SceneOptions options;
        options.kind = lasgen::SceneKind::deck;
        test::write_file(dir.file("deck.las"),
                         test::make_las(lasgen::LasLayout{}, lasgen::make_scene(options), 60000, 1));
        const CellGrid g = test::accumulate_file(dir.file("deck.las"), AccumulateOptions{});
        const std::vector<std::array<float, 9>> whole =
            triangles_in_x(extract_sheet(g, automatic_iso(g)), -everywhere, everywhere);
        CHECK(whole.size() > 20000);
        CHECK(count_differing(whole, tiled(g, 32)) == 0);
        // In the tiles' order, the whole grid's sheet is the tiles' sheet array for array.
        const Mesh ordered = in_tile_order(extract_sheet(g, automatic_iso(g)), g.spec, 32);
        const Mesh got = extract_sheet_in_tiles(g, automatic_iso(g), 32, 8);
        CHECK(ordered.triangles.size() == whole.size());
        CHECK(ordered.triangles == got.triangles);
        CHECK(ordered.positions == got.positions);
        CHECK(ordered.colors == got.colors);
        CHECK(ordered.normals == got.normals);
    }
}

TEST_CASE("the tiles' planes faced together: each tile's own facing is not the whole grid's") {
    // Not vacuous: faced by each tile alone (plane_facing of its own planes), the tiles' planes
    // face otherwise than the whole grid's in places; faced together, as the whole grid's.
    const CellGrid g = floor_plate_rail();
    const double iso = automatic_iso(g);
    const std::vector<std::array<std::int64_t, 4>> windows = tile_windows(g.spec, 16);
    const TilePart part_of = [&](const std::array<std::int64_t, 4>& w) {
        return bricks_within(g, w[0] - 8, w[1] + 8, w[2] - 8, w[3] + 8);
    };
    const SheetSurvey survey = survey_tiles(g.spec, windows, part_of, iso, false).survey;
    const PlaneFacing together = face_tiles(g.spec, windows, part_of, iso, survey);
    CHECK(!together.turned.empty());
    CHECK(std::is_sorted(together.turned.begin(), together.turned.end()));
    std::size_t own_differs = 0, planes = 0;
    for (const auto& w : windows) {
        const CellGrid part = part_of(w);
        if (part.cells.empty()) continue;
        const UnfacedPlanes unfaced = unfaced_planes(part, iso, survey, w);
        planes += unfaced.key.size();
        const PlaneFacing own = plane_facing({unfaced}, g.spec, survey);
        for (const std::uint64_t key : unfaced.key)
            own_differs += std::binary_search(own.turned.begin(), own.turned.end(), key) !=
                           std::binary_search(together.turned.begin(), together.turned.end(), key);
    }
    CAPTURE(planes);
    CHECK(planes > 1000);
    CHECK(own_differs > 0);
}

// The corners whose sample (value, normal or flags) the tiles give otherwise than the whole grid's sheet.
std::size_t seam_differences(const SeamCorners& got, const SeamCorners& expected) {
    std::size_t differ = 0;
    for (std::size_t i = 0; i < got.corners.size(); ++i)
        differ += got.value[i] != expected.value[i] || got.normal[i] != expected.normal[i] ||
                  got.flags[i] != expected.flags[i];
    return differ;
}

// The whole grid's sheet's samples at the corners of `cells` (seam_corners_of).
SeamCorners sampled_by_whole_grid(const CellGrid& g, double iso, const std::vector<std::uint64_t>& cells) {
    const std::array<std::int64_t, 3> dims{g.spec.dims[0], g.spec.dims[1], g.spec.dims[2]};
    SeamCorners sampled = seam_corners_of(cells, dims);
    SeamRequest request{sampled, [&](SeamCorners&& c) { sampled = std::move(c); }};
    CellGrid copy = g;
    extract_sheet(std::move(copy), iso, LinearParts::planes, {}, &request);
    return sampled;
}

TEST_CASE("tiles find the whole grid's thin cells and sample the seam's corners as its sheet does") {
    // The rail (5 cm across, cells of 6.4 cm) is thin; tiles of 16 and 24 cells with halos of 8
    // cut it, the plate and the floor. Their thin cells, gathered, are the whole grid's; their
    // samples at the corners of the cells a cell round the rail, each corner from the tile that
    // owns it, are those the whole grid's sheet gives.
    const CellGrid g = floor_plate_rail();
    const double iso = automatic_iso(g);
    const std::vector<std::array<std::int64_t, 3>> thin = thin_cells(g, iso);
    REQUIRE(thin.size() > 40);
    const std::array<std::int64_t, 3> dims{g.spec.dims[0], g.spec.dims[1], g.spec.dims[2]};
    const SeamCorners expected = sampled_by_whole_grid(g, iso, blocks_around(thin, dims, 0, 1));
    REQUIRE(expected.value.size() == expected.corners.size());
    const auto defined = std::count_if(expected.flags.begin(), expected.flags.end(),
                                       [](std::uint8_t f) { return (f & SeamCorners::defined) != 0; });
    CHECK(defined > std::ptrdiff_t(expected.corners.size() / 4));
    for (const std::int64_t tile : {16, 24}) {
        CAPTURE(tile);
        const std::vector<std::array<std::int64_t, 4>> windows = tile_windows(g.spec, tile);
        const TilePart part_of = [&](const std::array<std::int64_t, 4>& w) {
            return bricks_within(g, w[0] - 8, w[1] + 8, w[2] - 8, w[3] + 8);
        };
        const TiledSurvey survey = survey_tiles(g.spec, windows, part_of, iso, true);
        CHECK(survey.thin == thin);
        SeamCorners got = seam_corners_of(blocks_around(thin, dims, 0, 1), dims);
        sheets_of_tiles(g.spec, windows, part_of, iso, survey.survey, &got);
        CHECK(seam_differences(got, expected) == 0);
    }
}

TEST_CASE("the thin parts joined to the tiles' sheet as to the whole grid's") {
    // The post meshed at half the cell and joined to the floor round its foot: with the tiles'
    // sheet (tiles of 16 cells, whose border runs by the post), the seam joined as with the whole
    // grid's sheet (the grid as one tile), and the same fine triangles.
    const CellGrid g = floor_post(false);
    const double iso = automatic_iso(g);
    RunReport r;
    const std::optional<ThinReadPlan> plan = plan_thin_read(thin_cells(g, iso), g.spec, g.axes, r);
    REQUIRE(plan);
    Refinement refined{plan->mesh_cells, floor_post(true)};
    REQUIRE(refined.fine.spec.cell_size == doctest::Approx(g.spec.cell_size / 2).epsilon(1e-12));
    const auto finest = [&](std::int64_t tile) {
        const std::vector<std::array<std::int64_t, 4>> windows = tile_windows(g.spec, tile);
        const TilePart part_of = [&](const std::array<std::int64_t, 4>& w) {
            return bricks_within(g, w[0] - 8, w[1] + 8, w[2] - 8, w[3] + 8);
        };
        const TiledSurvey survey = survey_tiles(g.spec, windows, part_of, iso, false);
        return finest_sheet_in_tiles(g.spec, windows, part_of, iso, true, survey.survey, &refined);
    };
    const TiledFinest whole = finest(64), tiled = finest(16);
    // The tiles sample the seam as the whole grid does.
    {
        const std::vector<std::array<std::int64_t, 4>> windows = tile_windows(g.spec, 16);
        const TilePart part_of = [&](const std::array<std::int64_t, 4>& w) {
            return bricks_within(g, w[0] - 8, w[1] + 8, w[2] - 8, w[3] + 8);
        };
        SeamCorners got = seam_corners_of(refined.cells, {g.spec.dims[0], g.spec.dims[1], g.spec.dims[2]});
        sheets_of_tiles(g.spec, windows, part_of, iso, survey_tiles(g.spec, windows, part_of, iso, false).survey, &got);
        CHECK(seam_differences(got, sampled_by_whole_grid(g, iso, refined.cells)) == 0);
    }
    REQUIRE(whole.seam);
    REQUIRE(tiled.seam);
    CAPTURE(whole.seam->open_before);
    CAPTURE(whole.seam->open_after);
    CAPTURE(tiled.seam->open_after);
    CHECK(whole.seam->joined >= 2);
    CHECK(whole.seam->open_after < 0.8 * whole.seam->open_before);
    CHECK(tiled.seam->joined == whole.seam->joined);
    CHECK(tiled.seam->open_after == doctest::Approx(whole.seam->open_after).epsilon(0.01));
    // The fine triangles (in the refined cells): the rail's tube, the same in both.
    const auto in_refined = [&](const Mesh& m) {
        Mesh kept = m;
        keep_triangles_in_blocks(kept, g.spec, 0, refined.cells, true);
        return triangles_in_x(kept, -1, 10);
    };
    const std::vector<std::array<float, 9>> expected = in_refined(whole.mesh);
    CHECK(expected.size() > 300);
    CHECK(count_differing(expected, in_refined(tiled.mesh)) == 0);
}

TEST_CASE("a part of the grid that cuts a box, meshed with the whole grid's outside, faces out as the whole does") {
    // The part (x from 3 m on) cuts the box (box_on_deck), so its own cells would leave the inside
    // open to the cut. Inside the part, 1 m from its cut, the triangles must be the whole grid's,
    // facing the same way.
    const CellGrid g = box_on_deck();
    const double iso = automatic_iso(g);
    const SheetSurvey survey = sheet_survey(g, iso);
    const CellGrid part = part_in_x(g, 24, 64); // from 3 m
    const std::vector<std::array<float, 9>> expected = triangles_in_x(extract_sheet(g, iso), 4, 8);
    const std::vector<std::array<float, 9>> got = triangles_in_x(extract_sheet(part, iso, survey), 4, 8);
    CAPTURE(expected.size());
    CHECK(expected.size() > 1000);
    CHECK(count_differing(expected, got) == 0);
}

TEST_CASE("a room of plates on a floor, scanned inside and out: the floor faces up on both sides of its walls") {
    // A room of 3 cm plates scanned on both faces (walls round x, y in 2..4 m, 1.5 m high, and a
    // roof) on a floor of 6 x 6 m, scanned inside the room too, but not in a strip 10 cm wide round
    // it outside (so that the floor inside is reached over the walls only), 1 cm of noise, about
    // 40 points a face per 6.25 cm cell. Each plate is one layer of cells, whose sheet is split
    // into its two faces; the floor inside meets the walls' inner faces, and the room's inside is
    // closed: no outside tells its floor's side. Triangles face by their winding (as a viewer
    // culls them), not by vertex normals.
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 23;
    auto next = [&] { return uniform(state); };
    auto noise = [&] { return (next() + next() + next() + next() - 2.0) * 1.7320508075688772 * 0.01; };
    while (points.size() < 360000) {
        const double x = 6 * next(), y = 6 * next();
        const double beyond = std::max({2 - x, x - 4, 2 - y, y - 4}); // past the room's walls
        if (!(beyond > 0 && beyond < 0.1)) points.push_back(point(x, y, noise()));
    }
    for (int i = 0; i < 240000; ++i) {
        const double side = i % 4 < 2 ? 2.0 : 4.0, face = side + (i % 2 ? 0.015 : -0.015), along = 2 + 2 * next();
        const double up = 1.5 * next();
        if (i % 8 < 4)
            points.push_back(point(face + noise(), along, up));
        else
            points.push_back(point(along, face + noise(), up));
    }
    for (int i = 0; i < 80000; ++i)
        points.push_back(point(2 + 2 * next(), 2 + 2 * next(), 1.5 + (i % 2 ? 0.015 : -0.015) + noise()));
    test::TempDir dir;
    test::write_file(dir.file("room.las"),
                     test::las_with_points(points, {-0.05, -0.05, -0.05}, {6.05, 6.05, 1.55}, 8, 3, 0.001));
    AccumulateOptions grid;
    grid.grid = GridRequest::longest(96);
    const CellGrid g = test::accumulate_file(dir.file("room.las"), grid);
    REQUIRE(g.moments_exact());
    const Mesh sheet = extract_sheet(g, automatic_iso(g));
    double floor_in = 0, floor_in_down = 0, floor_out = 0, floor_out_down = 0, walls = 0, walls_in = 0, roof = 0,
           roof_in = 0;
    for (const auto& t : sheet.triangles) {
        std::array<double, 3> c{}, n{};
        const auto& a = sheet.positions[t[0]];
        const auto& b = sheet.positions[t[1]];
        const auto& d = sheet.positions[t[2]];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        for (int k = 0; k < 3; ++k) c[k] = sheet.origin[k] + (a[k] + b[k] + d[k]) / 3;
        const double area = triangle_area(sheet, t);
        const bool inside = c[0] > 2.2 && c[0] < 3.8 && c[1] > 2.2 && c[1] < 3.8;
        const bool outside = c[0] < 1.8 || c[0] > 4.2 || c[1] < 1.8 || c[1] > 4.2;
        if (c[2] < 0.1 && inside) floor_in += area, floor_in_down += n[2] < 0 ? area : 0;
        if (c[2] < 0.1 && outside && c[0] > 0.2 && c[0] < 5.8 && c[1] > 0.2 && c[1] < 5.8)
            floor_out += area, floor_out_down += n[2] < 0 ? area : 0;
        // A wall's face: away from its plate's middle (the nearer of x or y = 2 or 4).
        const double dx = c[0] - (c[0] < 3 ? 2.0 : 4.0), dy = c[1] - (c[1] < 3 ? 2.0 : 4.0);
        const bool along_x = std::abs(c[0] - 3) < 0.8;
        const bool along_y = std::abs(c[1] - 3) < 0.8;
        if (c[2] > 0.3 && c[2] < 1.2 && ((along_x && std::abs(dy) < 0.1) || (along_y && std::abs(dx) < 0.1)))
            walls += area, walls_in += (along_x ? dy * n[1] : dx * n[0]) < 0 ? area : 0;
        if (c[2] > 1.4 && inside) roof += area, roof_in += (c[2] - 1.5) * n[2] < 0 ? area : 0;
    }
    CAPTURE(floor_in);
    CAPTURE(floor_out);
    CAPTURE(walls);
    CAPTURE(roof);
    REQUIRE(floor_in > 2);
    REQUIRE(floor_out > 25);
    CHECK(floor_in_down == 0);
    CHECK(floor_out_down == 0);
    // Both faces of every wall and of the roof (twice their area), each facing out of its plate.
    CHECK(walls > 2 * 0.9 * 4 * 1.6 * 0.9);
    CHECK(walls_in < 0.01 * walls);
    CHECK(roof > 2 * 0.9 * 1.6 * 1.6);
    CHECK(roof_in < 0.01 * roof);
}
