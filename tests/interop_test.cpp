// SPDX-License-Identifier: Apache-2.0
// Outputs other programs open (issue 13): normals in every format, the plain .glb (names,
// double-sided material, origin in extras, 16-bit indices), Draco's scalar origin entries.
#include "io/draco_reader.hpp"
#include "io/draco_writer.hpp"
#include "io/gltf_reader.hpp"
#include "io/gltf_writer.hpp"
#include "io/ply_reader.hpp"
#include "io/ply_writer.hpp"
#include "lasmesh/normals.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>
#include <draco/compression/decode.h>

#include <cmath>
#include <cstring>

using namespace lasmesh;

namespace {

// A closed, outward-wound UV sphere of radius 2 around (1, 2, 3), at UTM-like origin, coloured.
Mesh sphere(int rings = 24, int segments = 48) {
    Mesh m;
    m.origin = {431249.96, 6700199.96, 87.5};
    m.cell_size = 0.25;
    const double pi = std::acos(-1.0);
    m.positions.push_back({1, 2, 5});
    for (int r = 1; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const double theta = pi * r / rings, phi = 2 * pi * s / segments;
            m.positions.push_back({float(1 + 2 * std::sin(theta) * std::cos(phi)),
                                   float(2 + 2 * std::sin(theta) * std::sin(phi)), float(3 + 2 * std::cos(theta))});
        }
    m.positions.push_back({1, 2, 1});
    const auto at = [&](int r, int s) { return std::uint32_t(1 + (r - 1) * segments + (s % segments)); };
    const std::uint32_t bottom = std::uint32_t(m.positions.size() - 1);
    for (int s = 0; s < segments; ++s) {
        m.triangles.push_back({0, at(1, s), at(1, s + 1)});
        for (int r = 1; r + 1 < rings; ++r) {
            m.triangles.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
            m.triangles.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
        }
        m.triangles.push_back({at(rings - 1, s), bottom, at(rings - 1, s + 1)});
    }
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        m.colors.push_back({std::uint8_t(i * 7 % 256), std::uint8_t(i * 13 % 256), std::uint8_t(i * 29 % 256)});
    return m;
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

} // namespace

TEST_CASE("normals: unit, outward on a closed sphere, (0, 0, 1) for unused vertices") {
    Mesh m = sphere();
    m.positions.push_back({9, 9, 9}); // no triangle uses it
    m.colors.push_back({0, 0, 0});
    compute_vertex_normals(m);
    REQUIRE(m.normals.size() == m.positions.size());
    for (std::size_t i = 0; i + 1 < m.positions.size(); ++i) {
        const auto& n = m.normals[i];
        CHECK(std::hypot(n[0], n[1], n[2]) == doctest::Approx(1).epsilon(1e-6));
        const double out[3] = {(m.positions[i][0] - 1) / 2.0, (m.positions[i][1] - 2) / 2.0,
                               (m.positions[i][2] - 3) / 2.0};
        CHECK(n[0] * out[0] + n[1] * out[1] + n[2] * out[2] > 0.99); // points where the triangles face
    }
    CHECK(m.normals.back() == std::array<float, 3>{0, 0, 1});
}

TEST_CASE("normals: PLY and Draco keep them") {
    Mesh m = sphere();
    compute_vertex_normals(m);
    test::TempDir dir;
    for (const bool ascii : {false, true}) {
        write_ply(m, dir.file("n.ply"), ascii);
        const Mesh back = read_ply(dir.file("n.ply"));
        CHECK(back.normals == m.normals);
        CHECK(back.colors == m.colors);
    }
    const Mesh d = decode_draco(encode_draco(m, {}), "test");
    REQUIRE(d.normals.size() == d.positions.size());
    for (std::size_t i = 0; i < d.positions.size(); ++i) { // Draco reorders: compare with the sphere's own
        const auto& n = d.normals[i];
        const double out[3] = {(d.positions[i][0] - 1) / 2.0, (d.positions[i][1] - 2) / 2.0,
                               (d.positions[i][2] - 3) / 2.0};
        CHECK(n[0] * out[0] + n[1] * out[1] + n[2] * out[2] > 0.98);
    }
}

TEST_CASE("draco: the origin also as three scalar doubles") {
    const std::string bytes = encode_draco(sphere(), {});
    draco::DecoderBuffer buffer;
    buffer.Init(bytes.data(), bytes.size());
    auto decoded = draco::Decoder().DecodeMeshFromBuffer(&buffer);
    REQUIRE(decoded.ok());
    const draco::GeometryMetadata* metadata = decoded.value()->GetMetadata();
    REQUIRE(metadata);
    double x = 0, y = 0, z = 0;
    CHECK(metadata->GetEntryDouble("origin_x", &x));
    CHECK(metadata->GetEntryDouble("origin_y", &y));
    CHECK(metadata->GetEntryDouble("origin_z", &z));
    CHECK(x == 431249.96);
    CHECK(y == 6700199.96);
    CHECK(z == 87.5);
}

TEST_CASE("glb: plain by default, named, double-sided, origin in extras, positions local") {
    Mesh m = sphere();
    compute_vertex_normals(m);
    GltfOptions options;
    options.name = "deck \"2\"";
    const std::string glb = encode_glb(m, options);
    const std::string json = test::glb_json(glb);
    CHECK(!has(json, "KHR_draco_mesh_compression"));
    CHECK(!has(json, "translation"));
    CHECK(has(json, "\"name\":\"deck \\\"2\\\"\""));
    CHECK(has(json, "\"doubleSided\":true"));
    CHECK(has(json, "\"extras\":{\"origin\":[431249.96,6700199.96,87.5],\"origin_gltf\":[431249.96,87.5,-6700199.96]"));
    CHECK(has(json, "\"NORMAL\":1"));
    CHECK(has(json, "\"componentType\":5123,\"count\":" + std::to_string(3 * m.triangles.size())));

    test::TempDir dir;
    write_glb(m, dir.file("p.glb"), options);
    const Mesh back = read_glb(dir.file("p.glb"));
    CHECK(back.positions == m.positions); // exact: plain floats
    CHECK(back.normals == m.normals);
    CHECK(back.colors == m.colors); // sRGB -> linear 16-bit -> sRGB is exact
    CHECK(back.triangles == m.triangles);
    CHECK(back.origin == m.origin);
    CHECK(back.cell_size == m.cell_size);

    options.origin = GltfOrigin::node; // a translation as well: read_glb still gives local positions
    write_glb(m, dir.file("n.glb"), options);
    CHECK(has(test::glb_json(encode_glb(m, options)), "\"translation\":[431249.96,87.5,-6700199.96]"));
    CHECK(read_glb(dir.file("n.glb")).origin == m.origin);
    CHECK(read_glb(dir.file("n.glb")).positions == m.positions);
}

TEST_CASE("glb: 32-bit indices above 65,535 vertices, Draco indices 16-bit below") {
    Mesh big = sphere(200, 400); // 79,602 vertices
    REQUIRE(big.positions.size() > 65535);
    CHECK(has(test::glb_json(encode_glb(big, {})),
              "\"componentType\":5125,\"count\":" + std::to_string(3 * big.triangles.size())));
    GltfOptions draco;
    draco.compression = GltfCompression::draco;
    const Mesh small = sphere();
    const std::string json = test::glb_json(encode_glb(small, draco));
    CHECK(has(json, "\"componentType\":5123,\"count\":" + std::to_string(3 * small.triangles.size())));
    CHECK(has(json, "\"doubleSided\":true"));
    test::TempDir dir;
    Mesh with_normals = small;
    compute_vertex_normals(with_normals);
    write_glb(with_normals, dir.file("d.glb"), draco);
    const Mesh back = read_glb(dir.file("d.glb"));
    CHECK(back.triangles.size() == small.triangles.size());
    CHECK(back.normals.size() == back.positions.size());
    CHECK(back.origin == small.origin);
}
