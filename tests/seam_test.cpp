// SPDX-License-Identifier: Apache-2.0
// The seam between the coarse mesh and the fine mesh of the thin parts: a flat layer of points
// meshed at a cell and at half of it, the halves kept on either side of a plane of cell faces,
// joined into one surface whose edges on that plane are each shared by two triangles.
#include "mesh/mesh_edit.hpp"
#include "mesh/seam.hpp"
#include "mesh/surface_sheet.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>

using namespace lasmesh;

namespace {

// A layer of cells holding 4 points each, at z layer `layer`, over the whole of x and y.
CellGrid layer_grid(const GridSpec& spec, std::uint32_t layer) {
    std::vector<std::uint64_t> count(spec.cell_count(), 0);
    for (std::uint64_t y = 0; y < spec.dims[1]; ++y)
        for (std::uint64_t x = 0; x < spec.dims[0]; ++x) count[(layer * spec.dims[1] + y) * spec.dims[0] + x] = 4;
    return test::grid_from_counts(spec, count);
}

// Per undirected edge, how many triangles use it; and whether a directed edge appears twice (two
// triangles facing opposite ways across it).
struct Edges {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    bool facing_apart = false;
};

Edges edges_of(const Mesh& m) {
    Edges e;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            ++e.uses[{std::min(a, b), std::max(a, b)}];
            e.facing_apart = e.facing_apart || ++directed[{a, b}] > 1;
        }
    return e;
}

// A joined mesh facing one way, every edge between at most two triangles, and no border left on
// the plane x = `x` (at least 16 edges there, each shared: two fine edges on each of 8 faces).
void check_closed_on_plane_x(const Mesh& joined, float x) {
    const Edges e = edges_of(joined);
    CHECK(!e.facing_apart);
    std::size_t on_plane = 0;
    for (const auto& [edge, uses] : e.uses) {
        CHECK(uses <= 2);
        if (joined.positions[edge.first][0] == x && joined.positions[edge.second][0] == x) {
            ++on_plane;
            CHECK(uses == 2);
        }
    }
    CHECK(on_plane >= 16);
}

// Cells of 1, `width` x 8 x 4; the points of the coarse grid's layer 1 at z = 1.5, of the fine
// grid's layer 3 at z = 1.75: two planes a quarter cell apart, as two meshes of one noisy
// surface are. The fine mesh is kept in the cells with x < `seam`, the coarse one in the others.
struct Layers {
    GridSpec coarse_spec;
    std::vector<std::uint64_t> fine_cells; // ascending
    Mesh coarse, fine;
};
Layers layers_meeting_at(std::uint32_t width, std::uint64_t seam) {
    Layers l;
    l.coarse_spec.dims = {width, 8, 4};
    GridSpec fine_spec = l.coarse_spec;
    fine_spec.cell_size = 0.5, fine_spec.dims = {2 * width, 16, 8};
    for (std::uint64_t z = 0; z < 4; ++z)
        for (std::uint64_t y = 0; y < 8; ++y)
            for (std::uint64_t x = 0; x < seam; ++x) l.fine_cells.push_back((z * 8 + y) * width + x);
    l.coarse = extract_sheet(layer_grid(l.coarse_spec, 1), 1);
    l.fine = extract_sheet(layer_grid(fine_spec, 3), 1);
    keep_triangles_in_blocks(l.coarse, l.coarse_spec, 0, l.fine_cells, false);
    keep_triangles_in_blocks(l.fine, l.coarse_spec, 0, l.fine_cells, true);
    return l;
}

} // namespace

TEST_CASE("the seam: the fine layer joined to the coarse one on the cell faces between them, facing its way") {
    // The fine mesh in the cells with x < 6 of 12, the coarse one in the others.
    const Layers l = layers_meeting_at(12, 6);
    const GridSpec& coarse_spec = l.coarse_spec;
    const std::vector<std::uint64_t>& fine_cells = l.fine_cells;
    const Mesh &coarse = l.coarse, &fine = l.fine;
    REQUIRE(!coarse.triangles.empty());
    REQUIRE(!fine.triangles.empty());
    const auto on_seam = [](const std::array<float, 3>& p) { return p[0] == 6.0f; };
    const auto check_joined = [&](const Mesh& joined, const SeamReport& seam, std::size_t fine_triangles) {
        // The 8 faces of the plane x = 6 the layer crosses, joined in one stretch: nothing left open.
        CHECK(seam.faces == 8);
        CHECK(seam.joined == 1);
        CHECK(seam.open_before == doctest::Approx(16)); // both borders, 8 long
        CHECK(seam.open_after == 0);
        // Every triangle kept; the coarse triangles on the seam split at the fine vertices.
        CHECK(joined.triangles.size() >= coarse.triangles.size() + fine_triangles + 8);
        const Edges e = edges_of(joined);
        CHECK(!e.facing_apart);
        std::size_t on_plane = 0;
        for (const auto& [edge, uses] : e.uses) {
            CHECK(uses <= 2);
            if (on_seam(joined.positions[edge.first]) && on_seam(joined.positions[edge.second])) {
                ++on_plane;
                CHECK(uses == 2); // no border left on the seam
            }
        }
        CHECK(on_plane >= 16); // the chains: two fine edges a face
        // The seam's vertices are the coarse ones, at z = 1.5 (the fine ones were at 1.75).
        for (const auto& p : joined.positions)
            if (on_seam(p)) CHECK(p[2] == doctest::Approx(1.5));
    };
    {
        Mesh joined = coarse;
        const SeamReport seam = append_joined(joined, fine, coarse_spec, fine_cells);
        check_joined(joined, seam, fine.triangles.size());
        // And the two layers still where they were away from the seam.
        std::size_t fine_kept = 0;
        for (const auto& p : joined.positions) fine_kept += p[2] == 1.75f;
        CHECK(fine_kept > 0);
    }
    {
        // The fine mesh facing down: it is turned to face up as the coarse one does, then joined.
        Mesh down = fine;
        for (auto& t : down.triangles) std::swap(t[1], t[2]);
        for (auto& n : down.normals)
            for (float& c : n) c = -c;
        Mesh joined = coarse;
        const SeamReport seam = append_joined(joined, down, coarse_spec, fine_cells);
        check_joined(joined, seam, down.triangles.size());
        for (std::size_t v = coarse.positions.size(); v < joined.normals.size(); ++v) CHECK(joined.normals[v][2] > 0);
    }
    {
        // A hole in the fine layer at the seam (its cube x 5.5-6, y 2.5-3 left out): the fine
        // border leaves the seam there, and is laid on either side of the hole; one border edge
        // is left on the seam, the coarse one across the hole, half a cell long.
        Mesh holed = fine;
        std::erase_if(holed.triangles, [&](const std::array<std::uint32_t, 3>& t) {
            double x = 0, y = 0;
            for (const std::uint32_t v : t) x += holed.positions[v][0] / 3, y += holed.positions[v][1] / 3;
            return x > 5.5 && y > 2.5 && y < 3;
        });
        REQUIRE(holed.triangles.size() < fine.triangles.size());
        Mesh joined = coarse;
        const SeamReport seam = append_joined(joined, holed, coarse_spec, fine_cells);
        CHECK(seam.faces == 8);
        CHECK(seam.joined == 2);
        CHECK(seam.open_after == doctest::Approx(0.5));
        const Edges e = edges_of(joined);
        CHECK(!e.facing_apart);
        std::size_t border_on_seam = 0;
        for (const auto& [edge, uses] : e.uses) {
            CHECK(uses <= 2);
            border_on_seam +=
                uses == 1 && on_seam(joined.positions[edge.first]) && on_seam(joined.positions[edge.second]);
        }
        CHECK(border_on_seam == 1);
    }
    {
        // No fine cells on the seam's other side: nothing to join, the meshes appended.
        Mesh joined = coarse;
        const SeamReport seam = append_joined(joined, Mesh{}, coarse_spec, fine_cells);
        CHECK(seam.faces == 0);
        CHECK(joined.triangles == coarse.triangles);
    }
}

TEST_CASE("the seam on the face between two bricks: joined as one inside a brick is") {
    // The plane x = 8 between the fine cells (x < 8) and the coarse ones is a face between bricks
    // of 4 cells: the coarse triangles next to it lie in bricks that hold no fine cell.
    const Layers l = layers_meeting_at(16, 8);
    Mesh joined = l.coarse;
    const SeamReport seam = append_joined(joined, l.fine, l.coarse_spec, l.fine_cells);
    CHECK(seam.faces == 8);
    CHECK(seam.joined == 1);
    CHECK(seam.open_after == 0);
    std::size_t on_plane = 0;
    for (const auto& [edge, uses] : edges_of(joined).uses)
        if (joined.positions[edge.first][0] == 8.0f && joined.positions[edge.second][0] == 8.0f) {
            ++on_plane;
            CHECK(uses == 2);
        }
    CHECK(on_plane >= 16);
}

TEST_CASE("the seam across faces: borders on different cells' faces, half a cell apart at most, joined") {
    // The coarse layer moved to z = 1.8 (its border on the faces of the cells z 1-2), the fine one
    // to z = 2.1 (on the faces of the cells z 2-3): no face holds both borders, yet they run side
    // by side, 0.3 apart, and are joined into one surface whose edges on x = 6 are each shared.
    Layers l = layers_meeting_at(12, 6);
    for (auto& p : l.coarse.positions) p[2] += 0.3f;
    for (auto& p : l.fine.positions) p[2] += 0.35f;
    Mesh joined = l.coarse;
    const SeamReport seam = append_joined(joined, l.fine, l.coarse_spec, l.fine_cells);
    CHECK(seam.faces == 0);
    CHECK(seam.joined == 1);
    CHECK(seam.open_before == doctest::Approx(16));
    CHECK(seam.open_after == 0);
    check_closed_on_plane_x(joined, 6.0f);
    for (const auto& p : joined.positions)
        if (p[0] == 6.0f) CHECK(p[2] == doctest::Approx(1.8));
    // Farther apart than half a cell (0.3 + 0.35 more), they are left as they were.
    for (auto& p : l.fine.positions) p[2] += 0.35f;
    Mesh apart = l.coarse;
    const SeamReport none = append_joined(apart, l.fine, l.coarse_spec, l.fine_cells);
    CHECK(none.joined == 0);
    CHECK(none.open_after == doctest::Approx(none.open_before));
}

TEST_CASE("the seam round a corner: coarse triangles with border edges on two faces, split on both") {
    // The coarse layer keeps one quadrant round the point x = 6, y = 4 (of 12 x 8 x 4 cells), the
    // fine one the rest; the quadrant's corner cube has border edges on the planes x = 6 and
    // y = 4, and in two of the four quadrants one of its triangles has both.
    for (const auto& [low_x, low_y] : {std::pair{false, false}, {true, false}, {false, true}, {true, true}}) {
        CAPTURE(low_x);
        CAPTURE(low_y);
        Layers l;
        l.coarse_spec.dims = {12, 8, 4};
        GridSpec fine_spec = l.coarse_spec;
        fine_spec.cell_size = 0.5, fine_spec.dims = {24, 16, 8};
        const auto coarse_cell = [&](std::uint64_t x, std::uint64_t y) { return (x < 6) == low_x && (y < 4) == low_y; };
        for (std::uint64_t z = 0; z < 4; ++z)
            for (std::uint64_t y = 0; y < 8; ++y)
                for (std::uint64_t x = 0; x < 12; ++x)
                    if (!coarse_cell(x, y)) l.fine_cells.push_back((z * 8 + y) * 12 + x);
        l.coarse = extract_sheet(layer_grid(l.coarse_spec, 1), 1);
        l.fine = extract_sheet(layer_grid(fine_spec, 3), 1);
        keep_triangles_in_blocks(l.coarse, l.coarse_spec, 0, l.fine_cells, false);
        keep_triangles_in_blocks(l.fine, l.coarse_spec, 0, l.fine_cells, true);
        REQUIRE(!l.coarse.triangles.empty());
        Mesh joined = l.coarse;
        const SeamReport seam = append_joined(joined, l.fine, l.coarse_spec, l.fine_cells);
        CHECK(seam.joined >= 1);
        CHECK(seam.open_before > 0);
        CHECK(seam.open_after < 0.1 * seam.open_before);
        const Edges e = edges_of(joined);
        CHECK(!e.facing_apart);
        const auto on_seam = [&](const std::array<float, 3>& p) {
            const bool x_side = low_x ? p[0] <= 6.0f : p[0] >= 6.0f, y_side = low_y ? p[1] <= 4.0f : p[1] >= 4.0f;
            return (p[0] == 6.0f && y_side) || (p[1] == 4.0f && x_side);
        };
        std::size_t on_planes = 0, open = 0;
        for (const auto& [edge, uses] : e.uses) {
            CHECK(uses <= 2);
            if (on_seam(joined.positions[edge.first]) && on_seam(joined.positions[edge.second]))
                ++on_planes, open += uses == 1;
        }
        CHECK(on_planes >= 16);
        CHECK(open <= 2); // at most the corner's own edges left
    }
}

TEST_CASE("the seam's faces: the fine sheet ends where the coarse one crosses them, and is joined there") {
    // The coarse layer's points at z = 1.7, the fine one's at z = 2.4: 0.7 apart, more than the
    // half cell within which borders are laid onto each other. Marched each on its own, the
    // borders stay apart; with the coarse sheet's values on the seam's faces (x = 6), the fine
    // sheet comes down to z = 1.7 there, and the two join into one surface.
    GridSpec coarse_spec;
    coarse_spec.dims = {12, 8, 4};
    GridSpec fine_spec = coarse_spec;
    fine_spec.cell_size = 0.5, fine_spec.dims = {24, 16, 8};
    const auto layer_at = [](const GridSpec& spec, std::uint32_t layer, double within) {
        CellGrid g = layer_grid(spec, layer);
        for (CellSums& c : g.cells) c.position[2] = c.count * static_cast<std::uint64_t>(within * 1000);
        return g;
    };
    std::vector<std::uint64_t> fine_cells;
    for (std::uint64_t z = 0; z < 4; ++z)
        for (std::uint64_t y = 0; y < 8; ++y)
            for (std::uint64_t x = 0; x < 6; ++x) fine_cells.push_back((z * 8 + y) * 12 + x);
    // `undefined_at`: a coarse corner on the seam's face made undefined, as if the coarse sheet were
    // (its cubes there unmeshed): so must the fine cubes round it be.
    const auto joined_at_seam = [&](bool seam_values, std::optional<std::array<std::int64_t, 3>> undefined_at = {}) {
        std::optional<SeamCorners> sampled;
        SeamRequest request{seam_corners_of(fine_cells, {12, 8, 4}), [&](SeamCorners&& c) { sampled = std::move(c); }};
        Mesh coarse = extract_sheet(layer_at(coarse_spec, 1, 0.7), 1, LinearParts::planes, {}, &request);
        REQUIRE(sampled);
        if (undefined_at) {
            const std::uint64_t key = sampled->key_of((*undefined_at)[0], (*undefined_at)[1], (*undefined_at)[2]);
            const auto at = std::lower_bound(sampled->corners.begin(), sampled->corners.end(), key);
            REQUIRE(*at == key);
            sampled->flags[static_cast<std::size_t>(at - sampled->corners.begin())] = 0;
        }
        const CellGrid fine_grid = layer_at(fine_spec, 4, 0.8);
        Mesh fine = seam_values ? extract_sheet(fine_grid, 1, LinearParts::planes,
                                                [&]() -> const SeamCorners& { return *sampled; })
                                : extract_sheet(fine_grid, 1);
        keep_triangles_in_blocks(coarse, coarse_spec, 0, fine_cells, false);
        keep_triangles_in_blocks(fine, coarse_spec, 0, fine_cells, true);
        REQUIRE(!coarse.triangles.empty());
        REQUIRE(!fine.triangles.empty());
        // Away from the seam the fine sheet keeps its own place.
        for (const auto& p : fine.positions)
            if (p[0] < 5.5f) CHECK(p[2] == doctest::Approx(2.4));
        if (undefined_at) // no fine triangle touches the fine points round it on the face x = 6
            for (const auto& t : fine.triangles)
                for (const std::uint32_t v : t) {
                    const auto& p = fine.positions[v];
                    CHECK(!(p[0] > 5.55f && std::abs(p[1] - 4.0f) < 0.4f));
                }
        Mesh joined = coarse;
        const SeamReport seam = append_joined(joined, fine, coarse_spec, fine_cells);
        return std::pair{seam, joined};
    };
    (void)joined_at_seam(true, std::array<std::int64_t, 3>{6, 4, 2});
    const auto [apart, unjoined] = joined_at_seam(false);
    CHECK(apart.joined == 0);
    CHECK(apart.open_after == doctest::Approx(16));
    const auto [seam, joined] = joined_at_seam(true);
    CHECK(seam.joined >= 1);
    CHECK(seam.open_before == doctest::Approx(16));
    CHECK(seam.open_after == 0);
    check_closed_on_plane_x(joined, 6.0f);
    for (const auto& p : joined.positions)
        if (p[0] == 6.0f) CHECK(p[2] == doctest::Approx(1.7));
}

TEST_CASE("the seam's faces: the coarse values a fine lattice point takes, and where it takes none") {
    // Cells of 1, 4 x 4 x 4; the cells with x < 2 refined. The coarse corners' values are their
    // z - 1.5 (a plane facing up), every one defined.
    SeamCorners c = seam_corners_of(
        [] {
            std::vector<std::uint64_t> cells;
            for (std::uint64_t z = 0; z < 4; ++z)
                for (std::uint64_t y = 0; y < 4; ++y)
                    for (std::uint64_t x = 0; x < 2; ++x) cells.push_back((z * 4 + y) * 4 + x);
            return cells;
        }(),
        {4, 4, 4});
    REQUIRE(c.corners.size() == 3 * 5 * 5);
    for (std::size_t i = 0; i < c.corners.size(); ++i) {
        const auto p = c.corner_of(c.corners[i]);
        c.value.push_back(static_cast<float>(p[2] - 1.5 + 0.1 * p[1]));
        c.normal.push_back({0, 0, 1});
        c.flags.push_back(SeamCorners::defined);
    }
    const std::array<double, 3> up{0, 0, 1}, down{0, 0, -1}, across{1, 0, 0};
    const SeamFaces faces(c);
    float v = 0;
    // Fine lattice points (in half cells): on the plane x = 2 (fine x = 4) between refined and not.
    CHECK(faces.coarse_value(4, 2, 2, up, v) == SeamFaces::Found::value); // a coarse corner (2, 1, 1)
    CHECK(v == doctest::Approx(1 - 1.5 + 0.1));
    CHECK(faces.coarse_value(4, 2, 3, up, v) == SeamFaces::Found::value); // mid-edge: z 1.5
    CHECK(v == doctest::Approx(1.5 - 1.5 + 0.1));
    CHECK(faces.coarse_value(4, 3, 3, up, v) == SeamFaces::Found::value); // mid-face: y 1.5, z 1.5
    CHECK(v == doctest::Approx(0.15));
    // A fine plane facing the other way takes the values negated.
    CHECK(faces.coarse_value(4, 3, 3, down, v) == SeamFaces::Found::value);
    CHECK(v == doctest::Approx(-0.15));
    // One running across the coarse plane is another surface: its own value stays.
    CHECK(faces.coarse_value(4, 3, 3, across, v) == SeamFaces::Found::off_seam);
    // Inside the refined cells, or among the others, or on a face between two refined cells.
    CHECK(faces.coarse_value(3, 3, 3, up, v) == SeamFaces::Found::off_seam);
    CHECK(faces.coarse_value(6, 3, 3, up, v) == SeamFaces::Found::off_seam);
    CHECK(faces.coarse_value(2, 3, 3, up, v) == SeamFaces::Found::off_seam);
    // On the grid's side (x = 0), with no coarse cells beyond: no seam either.
    CHECK(faces.coarse_value(0, 3, 3, up, v) == SeamFaces::Found::off_seam);
    // Where the coarse sheet is undefined at a corner it interpolates, or rejects the crossing
    // on an edge it lies on, the fine sample is undefined too (the coarse cube there is not meshed).
    const auto at = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
        return static_cast<std::size_t>(std::lower_bound(c.corners.begin(), c.corners.end(), c.key_of(x, y, z)) -
                                        c.corners.begin());
    };
    c.flags[at(2, 1, 2)] = 0;
    CHECK(faces.coarse_value(4, 3, 3, up, v) == SeamFaces::Found::undefined); // mid-face (2, 1.5, 1.5)
    CHECK(faces.coarse_value(4, 2, 2, up, v) == SeamFaces::Found::value);     // (2, 1, 1)
    // ... undefined whatever the normals: an undefined corner is not masked by one running across.
    CHECK(faces.coarse_value(4, 3, 3, across, v) == SeamFaces::Found::undefined);
    c.flags[at(2, 1, 2)] = SeamCorners::defined;
    // The edge up z from (2, 1, 1): rejected.
    c.flags[at(2, 1, 1)] = SeamCorners::defined | 1u << (1 + 2);
    CHECK(faces.coarse_value(4, 2, 3, up, v) == SeamFaces::Found::undefined); // on that edge
    CHECK(faces.coarse_value(4, 3, 3, up, v) == SeamFaces::Found::undefined); // on a face it bounds
    CHECK(faces.coarse_value(4, 3, 2, up, v) == SeamFaces::Found::value);     // on the edge along y
    c.flags[at(2, 1, 1)] = SeamCorners::defined;
    // The face's other edges: up z from (2, 2, 1) bounds it, up z from (2, 1, 2) does not.
    c.flags[at(2, 2, 1)] = SeamCorners::defined | 1u << (1 + 2);
    CHECK(faces.coarse_value(4, 3, 3, up, v) == SeamFaces::Found::undefined);
    c.flags[at(2, 2, 1)] = SeamCorners::defined;
    c.flags[at(2, 1, 2)] = SeamCorners::defined | 1u << (1 + 2);
    CHECK(faces.coarse_value(4, 3, 3, up, v) == SeamFaces::Found::value);
    c.flags[at(2, 1, 2)] = SeamCorners::defined;
    // The same surface within 60 degrees of the fine plane, another past it.
    const double c50 = std::cos(50 * std::numbers::pi / 180), c70 = std::cos(70 * std::numbers::pi / 180);
    CHECK(faces.coarse_value(4, 3, 3, {std::sqrt(1 - c50 * c50), 0, c50}, v) == SeamFaces::Found::value);
    CHECK(v == doctest::Approx(0.15));
    CHECK(faces.coarse_value(4, 3, 3, {std::sqrt(1 - c70 * c70), 0, c70}, v) == SeamFaces::Found::off_seam);
}

TEST_CASE("the seam's faces round an inner corner: an L of refined cells meets the others on two faces and the edge "
          "between") {
    // Cells of 1, 4 x 4 x 4; the cells with x < 2 or y < 2 refined (an L in x and y, every z): the
    // others (x, y >= 2) meet it on the faces x = 2 and y = 2 and along the edge x = y = 2, where
    // three of the four cells round it are refined. Coarse values z - 1.5 + 0.1 y.
    std::vector<std::uint64_t> cells;
    for (std::uint64_t z = 0; z < 4; ++z)
        for (std::uint64_t y = 0; y < 4; ++y)
            for (std::uint64_t x = 0; x < 4; ++x)
                if (x < 2 || y < 2) cells.push_back((z * 4 + y) * 4 + x);
    SeamCorners c = seam_corners_of(cells, {4, 4, 4});
    // Every corner but those of the unrefined cells alone (x, y >= 3).
    REQUIRE(c.corners.size() == 125 - 2 * 2 * 5);
    for (std::size_t i = 0; i < c.corners.size(); ++i) {
        const auto p = c.corner_of(c.corners[i]);
        CHECK(!(p[0] >= 3 && p[1] >= 3));
        c.value.push_back(static_cast<float>(p[2] - 1.5 + 0.1 * p[1]));
        c.normal.push_back({0, 0, 1});
        c.flags.push_back(SeamCorners::defined);
    }
    const std::array<double, 3> up{0, 0, 1};
    const SeamFaces faces(c);
    float v = 0;
    // Fine lattice points (half cells). On the inner edge x = y = 2, mid-way up a coarse edge.
    CHECK(faces.coarse_value(4, 4, 3, up, v) == SeamFaces::Found::value);
    CHECK(v == doctest::Approx(0.2));
    // ... and at a coarse corner on it.
    CHECK(faces.coarse_value(4, 4, 2, up, v) == SeamFaces::Found::value);
    CHECK(v == doctest::Approx(1 - 1.5 + 0.2));
    // On the face x = 2 past the edge (y 2.5), and on the face y = 2 (x 2.5): mid-face.
    CHECK(faces.coarse_value(4, 5, 3, up, v) == SeamFaces::Found::value);
    CHECK(v == doctest::Approx(0.25));
    CHECK(faces.coarse_value(5, 4, 3, up, v) == SeamFaces::Found::value);
    CHECK(v == doctest::Approx(0.2));
    // On the plane x = 2 but inside the L (y < 2: refined on both sides), and inside the unrefined
    // cells (x, y 2.5): no seam.
    CHECK(faces.coarse_value(4, 1, 3, up, v) == SeamFaces::Found::off_seam);
    CHECK(faces.coarse_value(4, 3, 3, up, v) == SeamFaces::Found::off_seam); // y 1.5: cells (1|2, 1), refined
    CHECK(faces.coarse_value(5, 5, 3, up, v) == SeamFaces::Found::off_seam);
    CHECK(faces.coarse_value(6, 6, 2, up, v) == SeamFaces::Found::off_seam); // corner (3, 3, 1): unrefined round it
}

TEST_CASE("the seam's corners: the coarse sheet's samples there, with the crossings it rejects") {
    // A step: the layer at z 1.5 for x < 6, at z 5.5 from x = 6 on (cells of 1, 12 x 8 x 8). The
    // cells x 5-6 are refined. The corners round the step sample either plane, and where a
    // vertical edge runs from one plane's samples to the other's, four cells apart, the sheet
    // rejects its crossing: the fine sheet must leave it open too (SeamFaces).
    GridSpec spec;
    spec.dims = {12, 8, 8};
    std::vector<std::uint64_t> count(spec.cell_count(), 0), refined;
    for (std::uint64_t y = 0; y < 8; ++y)
        for (std::uint64_t x = 0; x < 12; ++x) count[((x < 6 ? 1 : 5) * 8 + y) * 12 + x] = 4;
    for (std::uint64_t z = 0; z < 8; ++z)
        for (std::uint64_t y = 0; y < 8; ++y)
            for (std::uint64_t x = 5; x < 7; ++x) refined.push_back((z * 8 + y) * 12 + x);
    std::optional<SeamCorners> sampled;
    SeamRequest request{seam_corners_of(refined, {12, 8, 8}), [&](SeamCorners&& c) { sampled = std::move(c); }};
    (void)extract_sheet(test::grid_from_counts(spec, count), 1, LinearParts::planes, {}, &request);
    REQUIRE(sampled);
    const SeamCorners& c = *sampled;
    REQUIRE(c.corners.size() == 3 * 9 * 9);
    std::size_t defined = 0, rejected = 0;
    for (std::size_t i = 0; i < c.corners.size(); ++i) {
        const auto p = c.corner_of(c.corners[i]);
        if (!(c.flags[i] & SeamCorners::defined)) continue;
        ++defined;
        // Defined corners carry their plane's normal (up) and its signed distance.
        CHECK(c.normal[i][2] == doctest::Approx(1));
        if (p[0] <= 5 && p[2] <= 3) CHECK(c.value[i] == doctest::Approx(p[2] - 1.5));
        rejected += c.flags[i] >> 3 & 1; // the edge up z
        if (c.flags[i] & 0b1110) {       // any: between the planes, round the step
            CHECK(p[2] >= 2);
            CHECK(p[2] <= 4);
        }
    }
    CHECK(defined > 0);
    CHECK(rejected >= 9); // for every y
}
