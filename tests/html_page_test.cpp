// SPDX-License-Identifier: Apache-2.0
// The .html page's mesh: decoded with meshoptimizer's own decoders it gives back every triangle
// (same vertices, same winding), every colour, heat-map colour and distance, the positions to the
// page's step and the normals to a 127th; the facts leave out what changes from run to run; the
// page holds the compressed data.
#include "io/html_writer.hpp"
#include "lasmesh/error.hpp"
#include "test_support.hpp"

#include <boost/archive/iterators/binary_from_base64.hpp>
#include <boost/archive/iterators/transform_width.hpp>
#include <doctest/doctest.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

using namespace lasmesh;

namespace {

// A wavy sheet of 40 x 30 vertices, 0.25 m apart at UTM-like coordinates, coloured and with
// normals, and one vertex no triangle uses (the page leaves it out).
Mesh wavy_sheet(int nx = 40, int ny = 30) {
    Mesh m;
    m.origin = {431250.125, 6700200.375, 12.5};
    m.cell_size = 0.25;
    m.crs = "EPSG:32631";
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const float z = static_cast<float>(0.7 * std::sin(i * 0.3) * std::cos(j * 0.2));
            m.positions.push_back({0.25f * i - 3.1f, 0.25f * j + 1.7f, z});
            m.colors.push_back({static_cast<std::uint8_t>(i * 6), static_cast<std::uint8_t>(j * 8),
                                static_cast<std::uint8_t>((i * j) % 256)});
            const float length = std::sqrt(1 + z * z);
            m.normals.push_back({-z / length * 0.5f, 0.1f, 1 / length});
        }
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            const std::uint32_t a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
            m.triangles.push_back({a, b, d});
            m.triangles.push_back({a, d, c});
        }
    m.positions.push_back({100, 100, 100}); // used by no triangle
    m.colors.push_back({1, 2, 3});
    m.normals.push_back({0, 0, 1});
    return m;
}

std::uint32_t u32_at(const std::string& bytes, std::size_t at) {
    std::uint32_t v = 0;
    for (int k = 3; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(bytes[at + k]);
    return v;
}

// A triangle as the integer positions of its corners, rotated so the smallest comes first (the
// winding kept).
using Corner = std::array<long long, 3>;
using Triangle = std::array<Corner, 3>;
Triangle rotated(Triangle t) {
    const auto first = std::min_element(t.begin(), t.end()) - t.begin();
    std::rotate(t.begin(), t.begin() + first, t.end());
    return t;
}

} // namespace

TEST_CASE("html page: the mesh decodes to the same triangles, colours, positions to the step, normals") {
    const Mesh mesh = wavy_sheet();
    HtmlOptions options;
    options.name = "sheet";
    options.facts_json = R"({"device":"cpu","points_read":5,"outputs":[],"seconds":{"total":1},)"
                         R"("peak_rss_bytes":7,"simplify":{"error":0.125,"seconds":0.5},)"
                         R"("thin_parts":{"cells":3,"read_seconds":0.25}})";
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) { // a heat map: colours and distances of their own
        options.heat_colors.push_back({static_cast<std::uint8_t>(v % 251), static_cast<std::uint8_t>(v / 7 % 256), 9});
        options.heat_distance.push_back(0.001 * static_cast<double>(v));
    }
    options.heat_scale = 0.5;
    const std::string data = encode_html_mesh(mesh, options);
    REQUIRE(data.substr(0, 4) == "LMSH");
    CHECK(u32_at(data, 4) == 1);
    const std::uint32_t header_length = u32_at(data, 8);
    const nlohmann::json header = nlohmann::json::parse(data.substr(12, header_length));
    const std::size_t start = (12 + header_length + 3) / 4 * 4;
    const std::size_t vertices = mesh.positions.size() - 1, triangles = mesh.triangles.size();
    CHECK(header["name"] == "sheet");
    CHECK(header["vertices"] == vertices);
    CHECK(header["triangles"] == triangles);
    CHECK(header["origin"] == nlohmann::json({431250.125, 6700200.375, 12.5}));
    CHECK(header["crs"] == "EPSG:32631");
    CHECK(header["facts"] ==
          nlohmann::json::parse(R"({"points_read":5,"simplify":{"error":0.125},"thin_parts":{"cells":3}})"));
    const double step = header["step"];
    CHECK(step <= 0.25 / 1000);
    CHECK(step <= 1e-4);
    CHECK(std::exp2(std::round(std::log2(step))) == step); // a power of two: step times integer is exact

    const auto buffer = [&](const char* name) {
        const auto& b = header["buffers"][name];
        return data.substr(start + b["offset"].get<std::size_t>(), b["length"].get<std::size_t>());
    };
    std::vector<std::array<std::int32_t, 3>> positions(vertices);
    std::vector<std::array<std::uint8_t, 4>> colors(vertices);
    std::vector<std::array<std::int8_t, 4>> normals(vertices);
    std::vector<unsigned int> indices(3 * triangles);
    std::vector<std::array<std::uint8_t, 4>> heat_colors(vertices);
    std::vector<float> heat_distance(vertices);
    const auto decode_vertices = [&](void* out, std::size_t size, const std::string& bytes) {
        return meshopt_decodeVertexBuffer(out, vertices, size, reinterpret_cast<const unsigned char*>(bytes.data()),
                                          bytes.size());
    };
    REQUIRE(decode_vertices(positions.data(), 12, buffer("positions")) == 0);
    REQUIRE(decode_vertices(colors.data(), 4, buffer("colors")) == 0);
    REQUIRE(decode_vertices(normals.data(), 4, buffer("normals")) == 0);
    REQUIRE(decode_vertices(heat_colors.data(), 4, buffer("heat_colors")) == 0);
    REQUIRE(decode_vertices(heat_distance.data(), 4, buffer("heat_distance")) == 0);
    CHECK(header["heat_scale"] == 0.5);
    const std::string index_bytes = buffer("indices");
    REQUIRE(meshopt_decodeIndexBuffer(indices.data(), indices.size(), 4,
                                      reinterpret_cast<const unsigned char*>(index_bytes.data()),
                                      index_bytes.size()) == 0);

    // Every decoded vertex is an original one (positions rounded to the step), with its colour and
    // its normal; every triangle is an original one, wound the same way.
    std::map<Corner, std::size_t> original;
    const auto corner = [&](const std::array<float, 3>& p) {
        return Corner{std::llround(p[0] / step), std::llround(p[1] / step), std::llround(p[2] / step)};
    };
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) original[corner(mesh.positions[v])] = v;
    double farthest_normal = 0;
    std::set<std::size_t> seen;
    for (std::size_t v = 0; v < vertices; ++v) {
        const Corner c{positions[v][0], positions[v][1], positions[v][2]};
        REQUIRE(original.count(c) == 1);
        const std::size_t o = original[c];
        seen.insert(o);
        for (int a = 0; a < 3; ++a) {
            CHECK(std::abs(c[a] * step - mesh.positions[o][a]) <= step / 2 * (1 + 1e-9));
            CHECK(colors[v][a] == mesh.colors[o][a]);
            CHECK(heat_colors[v][a] == options.heat_colors[o][a]);
            farthest_normal = std::max(farthest_normal, std::abs(normals[v][a] / 127.0 - mesh.normals[o][a]));
        }
        CHECK(colors[v][3] == 255);
        CHECK(heat_distance[v] == static_cast<float>(options.heat_distance[o]));
    }
    CHECK(seen.size() == vertices);
    CHECK(seen.count(mesh.positions.size() - 1) == 0);
    CHECK(farthest_normal <= 0.5 / 127 + 1e-6);
    std::multiset<Triangle> expected, decoded;
    for (const auto& t : mesh.triangles)
        expected.insert(
            rotated({corner(mesh.positions[t[0]]), corner(mesh.positions[t[1]]), corner(mesh.positions[t[2]])}));
    for (std::size_t t = 0; t < triangles; ++t) {
        Triangle tri;
        for (int k = 0; k < 3; ++k) {
            const auto& p = positions[indices[3 * t + k]];
            tri[k] = {p[0], p[1], p[2]};
        }
        decoded.insert(rotated(tri));
    }
    CHECK(decoded == expected);
}

TEST_CASE(
    "html page: the page holds the data, compressed; the same mesh gives the same bytes; an empty mesh is refused") {
    const Mesh mesh = wavy_sheet();
    const HtmlOptions options;
    if (html_viewer_script().empty()) {
        CHECK_THROWS_AS(encode_html(mesh, options), Error);
        MESSAGE("this build has no HTML viewer (three.js and esbuild were not installed): page not checked");
        return;
    }
    const std::string page = encode_html(mesh, options);
    CHECK(page.rfind("<!doctype html>", 0) == 0);
    CHECK(page.find("@LASMESH_") == std::string::npos);
    CHECK(encode_html(mesh, options) == page);
    const std::string mark = "id=\"lasmesh-mesh\">";
    const std::size_t from = page.find(mark) + mark.size(), to = page.find("</script>", from);
    std::string text = page.substr(from, to - from);
    while (!text.empty() && text.back() == '=') text.pop_back();
    using namespace boost::archive::iterators;
    using Decoder = transform_width<binary_from_base64<std::string::const_iterator>, 8, 6>;
    const std::string compressed(Decoder(text.begin()), Decoder(text.end()));
    const std::string data = encode_html_mesh(mesh, options);
    std::string inflated(data.size(), '\0');
    uLongf size = static_cast<uLongf>(inflated.size());
    REQUIRE(uncompress(reinterpret_cast<Bytef*>(inflated.data()), &size,
                       reinterpret_cast<const Bytef*>(compressed.data()),
                       static_cast<uLong>(compressed.size())) == Z_OK);
    CHECK(size == data.size());
    CHECK(inflated == data);
    CHECK(compressed.size() < data.size());

    Mesh empty = mesh;
    empty.triangles.clear();
    CHECK_THROWS_AS(encode_html(empty, options), Error);
}

TEST_CASE("html page: lighter copies for moving, on the page's vertices, each a quarter of the one before") {
    struct Levels {
        std::vector<std::array<std::int32_t, 3>> positions;
        std::vector<std::vector<unsigned int>> levels;
    };
    const auto levels_of = [](const Mesh& mesh) {
        const std::string data = encode_html_mesh(mesh, HtmlOptions{});
        const std::uint32_t header_length = u32_at(data, 8);
        const nlohmann::json header = nlohmann::json::parse(data.substr(12, header_length));
        const std::size_t start = (12 + header_length + 3) / 4 * 4, vertices = header["vertices"];
        const auto buffer = [&](const std::string& name) {
            const auto& b = header["buffers"][name];
            return data.substr(start + b["offset"].get<std::size_t>(), b["length"].get<std::size_t>());
        };
        Levels out;
        out.positions.resize(vertices);
        const std::string positions = buffer("positions");
        REQUIRE(meshopt_decodeVertexBuffer(out.positions.data(), vertices, 12,
                                           reinterpret_cast<const unsigned char*>(positions.data()),
                                           positions.size()) == 0);
        for (const auto& level : header["motion"]) {
            const std::string bytes = buffer(level["buffer"].get<std::string>());
            std::vector<unsigned int> indices(3 * level["triangles"].get<std::size_t>());
            REQUIRE(meshopt_decodeIndexBuffer(indices.data(), indices.size(), 4,
                                              reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()) == 0);
            for (unsigned int v : indices) REQUIRE(v < vertices);
            out.levels.push_back(std::move(indices));
        }
        return out;
    };
    const Mesh mesh = wavy_sheet(160, 120); // 37,842 triangles over 39.75 x 29.75 units
    const Levels page = levels_of(mesh);
    REQUIRE(page.levels.size() == 3);
    std::size_t finer = mesh.triangles.size();
    for (const auto& level : page.levels) {
        const std::size_t triangles = level.size() / 3;
        CHECK(triangles <= finer / 4 + finer / 8);
        CHECK(triangles >= finer / 8);
        finer = triangles;
        int degenerate = 0;
        std::array<double, 2> low{1e300, 1e300}, high{-1e300, -1e300};
        for (std::size_t t = 0; t < level.size(); t += 3)
            degenerate += level[t] == level[t + 1] || level[t + 1] == level[t + 2] || level[t] == level[t + 2];
        for (unsigned int v : level)
            for (int a = 0; a < 2; ++a) {
                low[a] = std::min(low[a], double(page.positions[v][a]));
                high[a] = std::max(high[a], double(page.positions[v][a]));
            }
        CHECK(degenerate == 0);
        // The whole sheet, not a part of it: its corners are kept.
        const double step = 39.75 / double(high[0] - low[0]);
        CHECK((high[1] - low[1]) * step == doctest::Approx(29.75).epsilon(0.001));
        CHECK(step <= 1e-4);
    }
    CHECK(page.levels.back().size() / 3 <= 1000);
    CHECK(page.levels[page.levels.size() - 2].size() / 3 > 1000);
    const Levels again = levels_of(mesh); // the same bytes
    CHECK((again.positions == page.positions && again.levels == page.levels));
    CHECK(levels_of(wavy_sheet(23, 23)).levels.empty()); // 968 triangles: drawn whole
}
