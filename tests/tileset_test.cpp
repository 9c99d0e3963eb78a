// SPDX-License-Identifier: Apache-2.0
// 3D Tiles: a tree of levels on one lattice, each tile's box around its content and its
// children, errors that shrink to 0 at the finest level, tiles of a level that meet without
// cracks, and a tileset placed on the globe where PROJ puts the data.
#include "io/json.hpp"
#include "lasmesh/build_mesh.hpp"
#include "lasmesh/mesh_files.hpp"
#include "measure/level_error.hpp"
#include "measure/mesh_distance.hpp"
#include "read/crs_transform.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

using namespace lasmesh;
namespace fs = std::filesystem;

namespace {

// `input` meshed with a grid of `grid` cells along its longest side to the tileset `json`, the
// mesh kept.
BuildResult build_tileset(const std::string& input, const std::string& json, int grid) {
    BuildOptions o;
    o.grid = GridRequest::longest(grid);
    OutputRequest tileset;
    tileset.path = json;
    o.outputs.push_back(tileset);
    o.keep_mesh = true;
    return build_mesh(input, o);
}

struct Site {
    test::TempDir dir;
    std::string input;
    explicit Site(int epsg) : input(dir.file("deck.las")) {
        lasgen::SceneOptions scene;
        scene.origin = {431250, 6700200, 10};
        lasgen::LasLayout layout;
        layout.epsg = epsg;
        test::write_file(input, test::make_las(layout, lasgen::make_scene(scene), 200000, 5));
    }
    BuildResult build(const std::string& json, int grid = 300) const { return build_tileset(input, json, grid); }
};

Json read_json(const std::string& path) {
    std::ifstream in(path);
    return Json::parse(in);
}

// Every node of the tree with its level and parent, depth first.
struct NodeAt {
    const Json* node;
    const Json* parent;
    int level;
};
void walk(const Json& node, const Json* parent, int level, std::vector<NodeAt>& out) {
    out.push_back({&node, parent, level});
    if (node.contains("children"))
        for (const Json& child : node["children"]) walk(child, &node, level + 1, out);
}

bool box_holds(const Json& box, const Vec3& p, double slack) {
    for (int a = 0; a < 3; ++a)
        if (std::abs(p[a] - box[a].get<double>()) > box[3 + 4 * a].get<double>() + slack) return false;
    return true;
}

// Edges used by one triangle only, after welding the vertices of `meshes` by exact position.
std::size_t border_edges(const std::vector<Mesh>& meshes) {
    std::map<std::array<float, 3>, std::uint32_t> index;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const Mesh& m : meshes)
        for (const auto& t : m.triangles) {
            std::uint32_t v[3];
            for (int k = 0; k < 3; ++k)
                v[k] = index.emplace(m.positions[t[k]], static_cast<std::uint32_t>(index.size())).first->second;
            for (int k = 0; k < 3; ++k) ++uses[std::minmax(v[k], v[(k + 1) % 3])];
        }
    std::size_t once = 0;
    for (const auto& [edge, count] : uses) once += count == 1;
    return once;
}

} // namespace

TEST_CASE("tileset: levels on one lattice, boxes around content and children, errors down to 0") {
    Site site(32631);
    const std::string json_path = site.dir.file("site.json");
    const BuildResult result = site.build(json_path);
    const Json tileset = read_json(json_path);
    CHECK(tileset["asset"]["version"] == "1.1");
    const Json& root = tileset["root"];
    CHECK(root["refine"] == "REPLACE");
    std::vector<NodeAt> nodes;
    walk(root, nullptr, 0, nodes);
    const std::size_t levels = tileset["extras"]["lasmesh"]["levels"].size();
    CHECK(levels >= 3); // 300 cells: 64, 128, 256 cells a tile edge...
    std::map<int, std::vector<Mesh>> contents;
    std::set<std::string> uris;
    for (const NodeAt& at : nodes) {
        const Json& node = *at.node;
        const double error = node["geometricError"];
        if (at.parent) CHECK(error <= (*at.parent)["geometricError"].get<double>());
        if (at.level + 1 == static_cast<int>(levels)) CHECK(error == 0);
        if (at.level + 1 < static_cast<int>(levels)) CHECK(error > 0);
        const Json& box = node["boundingVolume"]["box"];
        if (at.parent) // a child's box lies within its parent's
            for (int corner = 0; corner < 8; ++corner) {
                Vec3 p;
                for (int a = 0; a < 3; ++a)
                    p[a] = box[a].get<double>() + (corner >> a & 1 ? 1 : -1) * box[3 + 4 * a].get<double>();
                CHECK(box_holds((*at.parent)["boundingVolume"]["box"], p, 1e-6));
            }
        if (!node.contains("content")) continue;
        const std::string uri = node["content"]["uri"];
        CHECK(uris.insert(uri).second);
        const Mesh tile = read_mesh(site.dir.file(uri));
        REQUIRE(!tile.triangles.empty());
        std::size_t outside = 0;
        for (const auto& p : tile.positions) outside += !box_holds(box, Vec3{p[0], p[1], p[2]}, 1e-4);
        CHECK(outside == 0);
        contents[at.level].push_back(tile);
    }
    // The finest level: the run's mesh, cut without cracks (welded, only its own borders are left).
    std::size_t triangles = 0;
    for (const Mesh& m : contents[static_cast<int>(levels) - 1]) triangles += m.triangles.size();
    CHECK(triangles == result.mesh->triangles.size());
    CHECK(border_edges(contents[static_cast<int>(levels) - 1]) == border_edges({*result.mesh}));
    CHECK(contents[static_cast<int>(levels) - 1].size() > 1);
    CHECK(contents[0].size() == 1);
    // Each coarser level within about a cell of its own of the finest (the deck's outlier
    // clusters, removed from the finest as small pieces, are not shown by the coarse levels).
    for (const Json& level : tileset["extras"]["lasmesh"]["levels"])
        CHECK(level["geometric_error"].get<double>() <= 2 * level["cell_size"].get<double>());
}

namespace {

// The tileset of `input` (a mesh in `crs`, the run's CRS) is where PROJ puts the data: the root's
// origin is PROJ's ECEF of the finest mesh's centre, every vertex of every finest tile goes through
// the root transform and PROJ back onto the run's mesh, and every normal turns as PROJ turns it,
// all within a centimetre (a quarter of a degree for normals).
void check_on_globe(const std::string& input, const std::string& crs, int grid, const test::TempDir& dir) {
    const std::string json_path = dir.file("site.json");
    const BuildResult result = build_tileset(input, json_path, grid);
    const Json tileset = read_json(json_path);
    REQUIRE(tileset["root"].contains("transform"));
    std::array<double, 16> m{};
    for (int i = 0; i < 16; ++i) m[i] = tileset["root"]["transform"][i];
    const CrsTransform to_run_crs(crs_from_text("EPSG:4978"), crs_from_text(crs), "test");
    const CrsTransform to_ecef(crs_from_text(crs), crs_from_text("EPSG:4978"), "test");
    const Mesh& mesh = *result.mesh;
    REQUIRE(!mesh.positions.empty());

    auto low = mesh.positions[0], high = low;
    for (const auto& p : mesh.positions)
        for (int a = 0; a < 3; ++a) low[a] = std::min(low[a], p[a]), high[a] = std::max(high[a], p[a]);
    double centre[3];
    for (int a = 0; a < 3; ++a) centre[a] = mesh.origin[a] + (double(low[a]) + high[a]) / 2;
    REQUIRE(to_ecef.apply(&centre[0], &centre[1], &centre[2], 1) == 1);
    CHECK(std::hypot(centre[0] - m[12], centre[1] - m[13], centre[2] - m[14]) < 0.01);

    const TriangleSearch search(mesh);
    const PointSearch mesh_vertices(mesh.positions);
    std::map<std::array<float, 3>, std::vector<std::uint32_t>> at_position;
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) at_position[mesh.positions[v]].push_back(v);
    double least_dot = 1; // a tile's normal against PROJ's turn of the mesh's normal at that vertex
    std::vector<NodeAt> nodes;
    walk(tileset["root"], nullptr, 0, nodes);
    double farthest = 0;
    std::size_t vertices = 0;
    for (const NodeAt& at : nodes) {
        if (!at.node->contains("content") || at.node->contains("children")) continue;
        const Mesh tile = read_mesh(dir.file((*at.node)["content"]["uri"]));
        for (std::size_t v = 0; v < tile.positions.size(); ++v) {
            const auto& p = tile.positions[v];
            double x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
            double y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
            double z = m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14];
            REQUIRE(to_run_crs.apply(&x, &y, &z, 1) == 1);
            const Vec3 local{x - mesh.origin[0], y - mesh.origin[1], z - mesh.origin[2]};
            farthest = std::max(farthest, search.distance(local));
            ++vertices;
            std::uint32_t nearest = 0;
            mesh_vertices.distance(local, &nearest);
            // Where a plate's two faces meet at its rim, each face has a vertex there, the normals
            // opposite: the tile's vertex is one of them.
            double best = -1;
            for (const std::uint32_t same : at_position[mesh.positions[nearest]]) {
                double ends[2][3];
                for (int e = 0; e < 2; ++e)
                    for (int a = 0; a < 3; ++a)
                        ends[e][a] = mesh.origin[a] + mesh.positions[same][a] + e * mesh.normals[same][a];
                REQUIRE(to_ecef.apply(&ends[0][0], &ends[0][1], &ends[0][2], 1) == 1);
                REQUIRE(to_ecef.apply(&ends[1][0], &ends[1][1], &ends[1][2], 1) == 1);
                const auto& n = tile.normals[v];
                double dot = 0, length = 0;
                for (int a = 0; a < 3; ++a) {
                    const double expected = ends[1][a] - ends[0][a];
                    dot += expected * (m[a] * n[0] + m[4 + a] * n[1] + m[8 + a] * n[2]);
                    length += expected * expected;
                }
                best = std::max(best, dot / std::sqrt(length));
            }
            least_dot = std::min(least_dot, best);
        }
    }
    CHECK(vertices > 150); // every vertex of every tile is checked: not a handful
    CHECK(farthest < 0.01);
    CHECK(least_dot > 0.99999); // within a quarter of a degree; the grid's turn here is about one degree
    // Up is up: the frame's third axis is the ellipsoid's normal at the centre, not the grid's z.
    const Vec3 up{m[8], m[9], m[10]}, origin{m[12], m[13], m[14]};
    const double r = std::hypot(origin[0], origin[1]);
    CHECK(std::abs(up[2] - std::sin(std::atan2(origin[2], r * (1 - 0.00669438)))) < 1e-3);
}

} // namespace

TEST_CASE("tileset: on the globe where PROJ puts the data, to a centimetre") {
    const Site site(32631);
    check_on_globe(site.input, "EPSG:32631", 300, site.dir);
}

// A file in longitude and latitude (meshed in the UTM zone of its centre, 15N) lands where PROJ
// puts it too: the frame follows the run's CRS, not the file's.
TEST_CASE("tileset: a file in degrees (EPSG:4326) on the globe, to a centimetre" * doctest::test_suite("shared")) {
    const std::filesystem::path folder = test::shared_las_folder();
    REQUIRE_MESSAGE(!folder.empty(), "../shared/data/las is absent (the unit_shared test is skipped then)");
    const test::TempDir dir;
    check_on_globe((folder / "PDAL_PDAL__test_data_las_epsg_4326.las").string(), "EPSG:32615", 200, dir);
}

TEST_CASE("tileset: the same bytes again; a new run replaces the tiles; no CRS: not placed, with a note") {
    Site site(32631);
    const std::string json_path = site.dir.file("site.json");
    site.build(json_path);
    const test::Bytes first = test::read_file(json_path);
    const std::string folder = read_json(json_path)["root"]["content"]["uri"].get<std::string>().substr(0, 21);
    CHECK(fs::is_directory(site.dir.file(folder)));
    site.build(json_path);
    CHECK(test::read_file(json_path) == first);
    site.build(json_path, 200); // other tiles: the earlier folder goes once the new tileset is in place
    CHECK(!fs::exists(site.dir.file(folder)));
    std::size_t folders = 0;
    for (const auto& entry : fs::directory_iterator(site.dir.path())) folders += entry.is_directory();
    CHECK(folders == 1);

    Site plain(0);
    const std::string local = plain.dir.file("local.json");
    const BuildResult result = plain.build(local);
    const Json tileset = read_json(local);
    CHECK(!tileset["root"].contains("transform"));
    CHECK(tileset["extras"]["lasmesh"]["note"].get<std::string>().find("no coordinate system") != std::string::npos);
    bool noted = false;
    for (const std::string& w : result.report.warnings)
        noted = noted || w.find("not placed on the globe") != std::string::npos;
    CHECK(noted);
}

TEST_CASE("tileset: a coarser level's triangles far from the finest are left out, in its own frame") {
    // The finest level: a square of 10 at z = 0. A coarser one, whose positions are relative to an
    // origin of its own: the same square 0.2 above, and a triangle 5 above (an outlier cluster
    // the finest level removed as a small piece, held together by the coarse cells).
    Mesh fine;
    fine.positions = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
    fine.triangles = {{0, 1, 2}, {0, 2, 3}};
    Mesh coarse;
    coarse.origin = {-1, 2, 0.5};
    const auto at = [&](double x, double y, double z) {
        return std::array<float, 3>{float(x - coarse.origin[0]), float(y - coarse.origin[1]),
                                    float(z - coarse.origin[2])};
    };
    coarse.positions = {at(0, 0, 0.2), at(10, 0, 0.2), at(10, 10, 0.2), at(0, 10, 0.2),
                        at(4, 4, 5),   at(6, 4, 5),    at(5, 6, 5)};
    coarse.triangles = {{0, 1, 2}, {4, 5, 6}, {0, 2, 3}};
    const FinestLevel finest(fine, 1000);
    CHECK(finest.remove_far(coarse, 1.0) == 1);
    CHECK(coarse.triangles == std::vector<std::array<std::uint32_t, 3>>{{0, 1, 2}, {0, 2, 3}});
    CHECK(coarse.positions.size() == 7); // the vertices stay: a tile takes only those it uses
    // Its error against the finest: the square's 0.2 either way.
    CHECK(finest.error(coarse) == doctest::Approx(0.2).epsilon(1e-4));
    // Half the square gone from the coarser level: the finest's points there lie up to 7 from the
    // half left, though every point of the coarser level still lies 0.2 from the finest.
    coarse.triangles.pop_back();
    CHECK(finest.error(coarse) > 3);
}
