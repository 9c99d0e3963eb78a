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
#include <map>

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
    const Edges e = edges_of(joined);
    CHECK(!e.facing_apart);
    std::size_t on_plane = 0;
    for (const auto& [edge, uses] : e.uses) {
        CHECK(uses <= 2);
        if (joined.positions[edge.first][0] == 6.0f && joined.positions[edge.second][0] == 6.0f) {
            ++on_plane;
            CHECK(uses == 2);
        }
    }
    CHECK(on_plane >= 16);
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
