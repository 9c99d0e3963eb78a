// SPDX-License-Identifier: Apache-2.0
// The measurement against the scene's true surfaces: exact distances to the primitives, and
// meshes whose errors are known by construction (a container's top, lifted; one sheet where a
// wall has two faces; a tube around a rail) reported part by part as they are.
#include "lasgen/truth.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

namespace {

using lasmesh::Vec3;

lasgen::Primitive find(const lasgen::Scene& s, const std::string& part, std::size_t nth = 0) {
    for (const lasgen::Primitive& p : s.primitives)
        if (p.part == part && nth-- == 0) return p;
    FAIL("no such primitive");
    return {};
}

// Adds the parallelogram origin + s u + t v (scene-local) to `mesh` as two triangles.
void add_quad(lasmesh::Mesh& mesh, const lasgen::Scene& s, const Vec3& o, const Vec3& u, const Vec3& v) {
    const auto first = static_cast<std::uint32_t>(mesh.positions.size());
    for (const Vec3& c : {o, Vec3{o[0] + u[0], o[1] + u[1], o[2] + u[2]},
                          Vec3{o[0] + u[0] + v[0], o[1] + u[1] + v[1], o[2] + u[2] + v[2]},
                          Vec3{o[0] + v[0], o[1] + v[1], o[2] + v[2]}}) {
        const Vec3 w = lasgen::to_world(s, c);
        mesh.positions.push_back({static_cast<float>(w[0] - mesh.origin[0]), static_cast<float>(w[1] - mesh.origin[1]),
                                  static_cast<float>(w[2] - mesh.origin[2])});
    }
    mesh.triangles.push_back({first, first + 1, first + 2});
    mesh.triangles.push_back({first, first + 2, first + 3});
}

lasgen::Scene deck() {
    lasgen::SceneOptions o;
    o.origin = {431250, 6700200, 10};
    return lasgen::make_scene(o);
}

const lasgen::PartError& part(const lasgen::TruthReport& r, const std::string& name) {
    for (const auto& p : r.parts)
        if (p.part == name) return p;
    FAIL("no part " << name);
    return r.parts.front();
}

lasgen::TruthOptions small() {
    lasgen::TruthOptions o;
    o.mesh_samples = 20'000;
    o.truth_samples = 200'000;
    return o;
}

} // namespace

TEST_CASE("distances to the primitives are exact, inside and past their edges") {
    lasgen::Primitive quad;
    quad.kind = lasgen::PrimitiveKind::quad;
    quad.origin = {0, 0, 0}, quad.u = {4, 0, 0}, quad.v = {0, 2, 0};
    CHECK(lasgen::distance_to(quad, {1, 1, 0.5}) == doctest::Approx(0.5));
    CHECK(lasgen::distance_to(quad, {1, 1, -0.25}) == doctest::Approx(0.25));
    CHECK(lasgen::distance_to(quad, {5, 1, 0}) == doctest::Approx(1.0));                // past an edge
    CHECK(lasgen::distance_to(quad, {7, 6, 0}) == doctest::Approx(5.0));                // past a corner
    CHECK(lasgen::distance_to(quad, {1, -3, 4}) == doctest::Approx(5.0));               // below an edge
    quad.v = {1, 2, 0};                                                                 // a parallelogram
    CHECK(lasgen::distance_to(quad, {4.9, 1.9, 0.3}) == doctest::Approx(0.3));          // inside only if sheared
    CHECK(lasgen::distance_to(quad, {0, 1, 0}) == doctest::Approx(1 / std::sqrt(5.0))); // past the slanted edge

    lasgen::Primitive tube;
    tube.kind = lasgen::PrimitiveKind::cylinder;
    tube.origin = {1, 1, 0}, tube.u = {0, 0, 10}, tube.radius = 0.5;
    CHECK(lasgen::distance_to(tube, {1, 1, 5}) == doctest::Approx(0.5));                   // on the axis
    CHECK(lasgen::distance_to(tube, {3, 1, 2}) == doctest::Approx(1.5));                   // outside
    CHECK(lasgen::distance_to(tube, {1.5, 1, 13}) == doctest::Approx(3.0));                // above the rim
    CHECK(lasgen::distance_to(tube, {1, 1, -4}) == doctest::Approx(std::hypot(4.0, 0.5))); // below, on the axis
    CHECK(lasgen::distance_to(tube, {4.5, 1, 14}) == doctest::Approx(5.0));                // past the rim, 3-4-5

    lasgen::Primitive torus;
    torus.kind = lasgen::PrimitiveKind::torus;
    torus.radius = 3, torus.minor_radius = 1;
    CHECK(lasgen::distance_to(torus, {0, 0, 0}) == doctest::Approx(2.0));
    CHECK(lasgen::distance_to(torus, {0, 3, 0.25}) == doctest::Approx(0.75));
    lasgen::Primitive sphere;
    sphere.kind = lasgen::PrimitiveKind::sphere;
    sphere.origin = {1, 2, 3}, sphere.radius = 2;
    CHECK(lasgen::distance_to(sphere, {1, 2, 8}) == doctest::Approx(3.0));
}

TEST_CASE("scene coordinates go to the world and back through the deck's tilt") {
    const lasgen::Scene s = deck();
    for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{64, 24, 7}, Vec3{10.5, -3, 2.25}}) {
        const Vec3 w = lasgen::to_world(s, p), back = lasgen::to_local(s, w);
        for (int a = 0; a < 3; ++a) CHECK(std::abs(back[a] - p[a]) < 1e-8); // doubles at 6.7 million metres
    }
    // The tilt is real: the deck's far corner is not at the origin's height in the world.
    CHECK(std::abs(lasgen::to_world(s, {64, 24, 0})[2] - 10) > 0.1);
    for (const lasgen::Primitive& p : s.primitives) CHECK(!p.part.empty());
}

TEST_CASE("a container's top, exact and lifted, is measured as it is") {
    const lasgen::Scene s = deck();
    lasmesh::Mesh mesh;
    mesh.origin = {431260, 6700205, 11};
    add_quad(mesh, s, {6, 3, 2.6}, {12, 0, 0}, {0, 2.5, 0}); // the first container's top
    const lasgen::TruthOptions o = small();
    lasgen::TruthReport r = lasgen::measure_against_truth(s, mesh, o);
    CHECK(r.mesh_area == doctest::Approx(30.0).epsilon(1e-5));
    CHECK(r.mean < 1e-5);
    CHECK(r.floating_share == 0);
    const auto& top = part(r, "containers");
    CHECK(top.mesh_area == doctest::Approx(30.0).epsilon(1e-5));
    CHECK(part(r, "deck").mesh_area == 0);
    // The containers' true surface: four boxes' tops and four sides, 105.4 + 59.2 + 59.2 + 103.4 m².
    CHECK(top.truth_area == doctest::Approx(327.2).epsilon(1e-9));
    CHECK(top.covered == doctest::Approx(30.0 / top.truth_area).epsilon(0.05));
    CHECK(part(r, "deck").covered == 0);
    // The deck's true area leaves out what stands on it.
    CHECK(part(r, "deck").truth_area ==
          doctest::Approx(64 * 24 - 12 * 2.5 - 6 * 2.5 - 6 * 2.5 - 6 * 2.5).epsilon(0.01));

    lasmesh::Mesh lifted;
    lifted.origin = mesh.origin;
    add_quad(lifted, s, {6, 3, 2.64}, {12, 0, 0}, {0, 2.5, 0});
    r = lasgen::measure_against_truth(s, lifted, o);
    CHECK(r.mean == doctest::Approx(0.04).epsilon(1e-3));
    CHECK(part(r, "containers").p99 == doctest::Approx(0.04).epsilon(1e-3));
    CHECK(part(r, "containers").covered > 0.05); // 4 cm: within the 5 cm tolerance

    lifted = {};
    lifted.origin = mesh.origin;
    add_quad(lifted, s, {6, 3, 2.66}, {12, 0, 0}, {0, 2.5, 0});
    r = lasgen::measure_against_truth(s, lifted, o);
    CHECK(part(r, "containers").covered < 0.005); // 6 cm: only where the sides come near

    lifted = {};
    lifted.origin = mesh.origin;
    add_quad(lifted, s, {6, 3, 3.0}, {12, 0, 0}, {0, 2.5, 0});
    r = lasgen::measure_against_truth(s, lifted, o);
    CHECK(r.floating_share > 0.99);
    CHECK(part(r, "containers").mesh_area < 0.01 * 30);
}

TEST_CASE("one sheet between a wall's two faces gets half their area, a fat tube twice a rail's") {
    const lasgen::Scene s = deck();
    lasmesh::Mesh mesh;
    mesh.origin = {431250, 6700200, 10};
    add_quad(mesh, s, {44, 6, 0}, {14, 0, 0}, {0, 0, 7}); // midway in the deckhouse's first wall
    // A tube of twice the top rail's radius around it (y = 0.3, z = 1.1, 3 cm): 64 flat sides.
    const lasgen::Primitive rail = find(s, "railings");
    REQUIRE(rail.radius == doctest::Approx(0.03));
    const int sides = 64;
    const double r2 = 2 * rail.radius, length = rail.u[0];
    for (int k = 0; k < sides; ++k) {
        const double a0 = 2 * std::numbers::pi * k / sides, a1 = 2 * std::numbers::pi * (k + 1) / sides;
        const Vec3 p0{rail.origin[0], rail.origin[1] + r2 * std::cos(a0), rail.origin[2] + r2 * std::sin(a0)};
        add_quad(mesh, s, p0, {length, 0, 0},
                 {0, r2 * (std::cos(a1) - std::cos(a0)), r2 * (std::sin(a1) - std::sin(a0))});
    }
    const lasgen::TruthReport r = lasgen::measure_against_truth(s, mesh, small());
    const auto& walls = part(r, "walls");
    CHECK(walls.mesh_area == doctest::Approx(14 * 7).epsilon(0.02));
    CHECK(walls.mean == doctest::Approx(0.015).epsilon(0.01));
    CHECK(walls.covered == doctest::Approx(2 * 14 * 7 / walls.truth_area).epsilon(0.05)); // both faces within 5 cm
    const double tube_area = 2 * std::numbers::pi * r2 * length;
    const auto& railings = part(r, "railings");
    CHECK(railings.mesh_area == doctest::Approx(tube_area).epsilon(0.03));
    CHECK(railings.mean == doctest::Approx(rail.radius).epsilon(0.02));
    // Twice the rail's own area, and the rail covered (3 cm away), the other rails not.
    CHECK(railings.mesh_area / (2 * std::numbers::pi * rail.radius * length) == doctest::Approx(2.0).epsilon(0.03));
    CHECK(railings.covered < 0.5);
    CHECK(railings.covered > 0.05);
    // The tube's sides are wound to face its axis: into the rail, none to its free side.
    CHECK(railings.faces_free_side == 0);
}

TEST_CASE("a mesh's triangles face their surfaces' free side by their winding: up, out of a plate, not in") {
    const lasgen::Scene s = deck();
    lasmesh::Mesh mesh;
    mesh.origin = {431250, 6700200, 10};
    add_quad(mesh, s, {6, 3, 2.6}, {12, 0, 0}, {0, 2.5, 0});  // the first container's top, wound up
    add_quad(mesh, s, {44, 5.985, 0}, {14, 0, 0}, {0, 0, 7}); // the deckhouse's first wall, outer face (-y)
    add_quad(mesh, s, {44, 6.015, 0}, {14, 0, 0}, {0, 0, 7}); // its inner face, wound out of the room (-y)
    add_quad(mesh, s, {30, 20, 0}, {2, 0, 0}, {0, 2, 0});     // the deck, wound up
    lasgen::TruthReport r = lasgen::measure_against_truth(s, mesh, small());
    CHECK(part(r, "containers").faces_free_side == 1);
    CHECK(part(r, "deck").faces_free_side == 1);
    // The two faces of the wall face one way: one of them into the plate's middle.
    CHECK(part(r, "walls").faces_free_side == doctest::Approx(0.5).epsilon(1e-6));
    CHECK(part(r, "pipes").faces_free_side == -1); // no mesh near them
    CHECK(r.faces_free_side == doctest::Approx((30.0 + 98 + 4) / (30 + 2 * 98 + 4)).epsilon(1e-6));

    lasmesh::Mesh turned;
    turned.origin = mesh.origin;
    add_quad(turned, s, {6, 3, 2.6}, {0, 2.5, 0}, {12, 0, 0}); // the top again, wound down
    r = lasgen::measure_against_truth(s, turned, small());
    CHECK(part(r, "containers").faces_free_side == 0);
}
