// SPDX-License-Identifier: Apache-2.0
// Draco (.drc) and glTF (.glb) output: round trips through the Draco library within the
// quantization step, exact colours, the local frame kept, deterministic bytes, refusals.
#include "io/draco_reader.hpp"
#include "io/draco_writer.hpp"
#include "io/gltf_reader.hpp"
#include "io/gltf_writer.hpp"
#include "io/srgb.hpp"
#include "lasmesh/error.hpp"
#include "mesh/marching_cubes.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>
#include <draco/compression/decode.h>

#include <cmath>
#include <cstring>
#include <fstream>

using namespace lasmesh;

namespace {

// A torus (genus 1) marched on a 32^3 grid of 0.25 m cells at UTM-like coordinates, coloured
// from its positions so that the colours vary over the whole 0-255 range.
Mesh torus_mesh(bool color = true) {
    test::DenseCells g;
    const std::uint32_t n = 32;
    g.spec.dims = {n, n, n};
    g.spec.cell_size = 0.25;
    g.spec.origin = {500000.125, 6700000.375, 12.5};
    g.count.resize(g.spec.cell_count());
    for (std::uint32_t k = 0; k < n; ++k)
        for (std::uint32_t j = 0; j < n; ++j)
            for (std::uint32_t i = 0; i < n; ++i) {
                const double ring = std::hypot(i + 0.5 - 16, j + 0.5 - 16) - 9;
                const double field = 10 * (4 - std::hypot(ring, k + 0.5 - 16));
                g.count[(std::uint64_t(k) * n + j) * n + i] =
                    static_cast<std::uint64_t>(std::max(0.0, std::round(field)));
            }
    Mesh m = extract_closed_surface(g, 5);
    m.normals.clear(); // the fixture is positions and colours; normals are tested in interop_test
    if (color)
        for (const auto& p : m.positions)
            m.colors.push_back({static_cast<std::uint8_t>(int(p[0] * 37) % 256),
                                static_cast<std::uint8_t>(int(p[1] * 53) % 256),
                                static_cast<std::uint8_t>(int(p[2] * 71) % 256)});
    return m;
}

// The enclosed volume (divergence theorem): positive only for closed, outward-wound meshes.
double volume(const Mesh& m) {
    double v = 0;
    for (const auto& t : m.triangles) {
        const auto &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
        v += (double(a[0]) * (double(b[1]) * c[2] - double(b[2]) * c[1]) -
              double(a[1]) * (double(b[0]) * c[2] - double(b[2]) * c[0]) +
              double(a[2]) * (double(b[0]) * c[1] - double(b[1]) * c[0])) /
             6;
    }
    return v;
}

// The Draco .glb with the origin in a translation node: what the tests below were written for.
const GltfOptions draco_node{GltfCompression::draco, GltfOrigin::node, "mesh", {}};

double chebyshev(const std::array<float, 3>& a, const std::array<float, 3>& b) {
    return std::max({std::abs(double(a[0]) - b[0]), std::abs(double(a[1]) - b[1]), std::abs(double(a[2]) - b[2])});
}

struct Match {
    double worst = 0;         // the largest distance (per axis) from a vertex to its nearest match
    bool colors_match = true; // every decoded vertex has an original within `tolerance` of its colour
};

// For every vertex of `decoded`, the nearest vertex of `original` (brute force: small meshes).
Match match_vertices(const Mesh& decoded, const Mesh& original, double tolerance) {
    Match result;
    for (std::size_t i = 0; i < decoded.positions.size(); ++i) {
        double best = 1e300;
        bool color_found = false;
        for (std::size_t j = 0; j < original.positions.size(); ++j) {
            const double d = chebyshev(decoded.positions[i], original.positions[j]);
            best = std::min(best, d);
            // Vertices closer than a step cannot be told apart: any of them may have the colour.
            if (d <= tolerance && !decoded.colors.empty() && decoded.colors[i] == original.colors[j])
                color_found = true;
        }
        result.worst = std::max(result.worst, best);
        if (!decoded.colors.empty() && !color_found) result.colors_match = false;
    }
    return result;
}

void check_round_trip(const Mesh& decoded, const Mesh& original, double step) {
    CHECK(decoded.triangles.size() == original.triangles.size());
    CHECK(decoded.positions.size() == original.positions.size());
    CHECK(decoded.colors.empty() == original.colors.empty());
    CHECK(decoded.origin == original.origin);
    CHECK(decoded.cell_size == original.cell_size);
    // Draco rounds to the nearest step: half a step per axis, plus float rounding.
    const Match there = match_vertices(decoded, original, step);
    CHECK(there.worst <= step / 2 * 1.001);
    CHECK(there.colors_match);
    const Match back = match_vertices(original, decoded, step);
    CHECK(back.worst <= step / 2 * 1.001);
    CHECK(volume(decoded) == doctest::Approx(volume(original)).epsilon(0.01));
    CHECK(volume(decoded) > 0);
}

// The BIN chunk of a GLB file, where write_glb puts the Draco stream at offset 0.
std::string glb_bin_chunk(const std::string& glb) {
    std::uint32_t json_length, bin_length;
    std::memcpy(&json_length, glb.data() + 12, 4);
    std::memcpy(&bin_length, glb.data() + 20 + json_length, 4);
    return glb.substr(28 + json_length, bin_length);
}

std::string read_text(const std::string& path) {
    const test::Bytes bytes = test::read_file(path);
    return std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

} // namespace

TEST_CASE("draco: sRGB to linear 16-bit and back is exact for every 8-bit value") {
    for (int v = 0; v < 256; ++v) {
        CAPTURE(v);
        REQUIRE(linear16_to_srgb8(srgb8_to_linear16(static_cast<std::uint8_t>(v))) == v);
        if (v > 0)
            REQUIRE(srgb8_to_linear16(static_cast<std::uint8_t>(v)) >
                    srgb8_to_linear16(static_cast<std::uint8_t>(v - 1)));
    }
    CHECK(srgb8_to_linear16(0) == 0);
    CHECK(srgb8_to_linear16(255) == 65535);
    CHECK(srgb8_to_linear16(128) == 14146); // 0.21586 linear: mid-grey is darker than half
    CHECK(srgb8_to_linear16(10) == 199);    // on the linear toe: 10 / 255 / 12.92 = 0.003035
}

TEST_CASE("draco: automatic position bits keep the step under a tenth of a cell") {
    Mesh m;
    m.positions = {{0, 0, 0}, {100, 10, 1}};
    m.cell_size = 1;
    CHECK(position_range(m) == 100);
    CHECK(automatic_position_bits(m) == 10); // 100 / 1023 <= 0.1 < 100 / 511
    CHECK(quantization_step(m, 10) == doctest::Approx(100.0 / 1023));
    m.cell_size = 0;
    CHECK(automatic_position_bits(m) == 14); // unknown cell
    m.cell_size = 1e-4;
    CHECK(automatic_position_bits(m) == 16); // capped
    m.cell_size = 1000;
    CHECK(automatic_position_bits(m) == 8); // floor
    CHECK(position_bits(m, DracoOptions{12, 7}) == 12);
    CHECK_THROWS_AS(position_bits(m, DracoOptions{31, 7}), Error);
    CHECK_THROWS_AS(position_bits(m, DracoOptions{0, 11}), Error);
}

TEST_CASE("draco: .drc round trip through the Draco decoder, within the step, colours exact") {
    const Mesh mesh = torus_mesh();
    REQUIRE(mesh.triangles.size() > 1000);
    const int bits = automatic_position_bits(mesh);
    const double step = quantization_step(mesh, bits);
    CHECK(step <= mesh.cell_size / 10);
    const std::string bytes = encode_draco(mesh, {});

    SUBCASE("the stream as Draco sees it") {
        draco::DecoderBuffer buffer;
        buffer.Init(bytes.data(), bytes.size());
        auto decoded = draco::Decoder().DecodeMeshFromBuffer(&buffer);
        REQUIRE(decoded.ok());
        const draco::Mesh& d = *decoded.value();
        CHECK(d.num_faces() == mesh.triangles.size());
        const draco::PointAttribute* position = d.GetAttributeByUniqueId(draco_position_id);
        const draco::PointAttribute* color = d.GetAttributeByUniqueId(draco_color_id);
        REQUIRE(position);
        REQUIRE(color);
        CHECK(position->attribute_type() == draco::GeometryAttribute::POSITION);
        CHECK(color->attribute_type() == draco::GeometryAttribute::COLOR);
        CHECK(color->data_type() == draco::DT_UINT8);
        CHECK(color->normalized());
        CHECK(color->num_components() == 3);
        REQUIRE(d.GetMetadata());
        std::vector<double> origin;
        double cell = 0;
        CHECK(d.GetMetadata()->GetEntryDoubleArray("origin", &origin));
        CHECK(origin == std::vector<double>{500000.125, 6700000.375, 12.5});
        CHECK(d.GetMetadata()->GetEntryDouble("cell_size", &cell));
        CHECK(cell == 0.25);
    }
    SUBCASE("read back") {
        test::TempDir dir;
        write_draco(mesh, dir.file("t.drc"), {});
        CHECK(read_text(dir.file("t.drc")) == bytes);
        check_round_trip(read_draco(dir.file("t.drc")), mesh, step);
    }
    SUBCASE("coarse and fine quantization: the error follows the step") {
        for (int b : {6, 9, 20}) {
            CAPTURE(b);
            const Mesh decoded = decode_draco(encode_draco(mesh, {b, 7}), "test");
            const double s = quantization_step(mesh, b);
            const double worst = match_vertices(decoded, mesh, s).worst;
            CHECK(worst <= s / 2 * 1.001 + 1e-6);
            if (b < 20) CHECK(worst >= s / 4); // the step is Draco's, not a loose bound
        }
    }
    SUBCASE("every level gives a mesh; higher levels are no larger") {
        const std::size_t fastest = encode_draco(mesh, {0, 0}).size(), smallest = encode_draco(mesh, {0, 10}).size();
        CHECK(smallest <= bytes.size());
        CHECK(bytes.size() < fastest);
        CHECK(decode_draco(encode_draco(mesh, {0, 0}), "test").triangles.size() == mesh.triangles.size());
    }
}

TEST_CASE("draco: .glb holds the same mesh, linear 16-bit colours, the origin in the node") {
    const Mesh mesh = torus_mesh();
    const double step = quantization_step(mesh, automatic_position_bits(mesh));
    const std::string glb = encode_glb(mesh, draco_node);
    REQUIRE(glb.size() > 28);
    CHECK(glb.compare(0, 4, "glTF") == 0);
    CHECK(glb.size() % 4 == 0);
    const std::string json = test::glb_json(glb);
    CHECK(json.size() % 4 == 0);
    CHECK(json.find("\"translation\":[500000.125,12.5,-6700000.375]") != std::string::npos);
    CHECK(json.find("\"extensionsRequired\":[\"KHR_draco_mesh_compression\"]") != std::string::npos);
    CHECK(json.find("\"attributes\":{\"POSITION\":0,\"COLOR_0\":1}") != std::string::npos);

    // The Draco stream in the BIN chunk, decoded by the library: colours are linear words.
    const std::string bin = glb_bin_chunk(glb);
    draco::DecoderBuffer buffer;
    buffer.Init(bin.data(), bin.size());
    auto decoded = draco::Decoder().DecodeMeshFromBuffer(&buffer);
    REQUIRE(decoded.ok());
    const draco::Mesh& d = *decoded.value();
    CHECK(d.num_faces() == mesh.triangles.size());
    const draco::PointAttribute* color = d.GetAttributeByUniqueId(draco_color_id);
    REQUIRE(color);
    CHECK(color->data_type() == draco::DT_UINT16);
    CHECK(color->normalized());
    // Each decoded point's colour is the linear form of some original colour.
    std::vector<bool> linear_value(65536);
    for (const auto& c : mesh.colors)
        for (int k = 0; k < 3; ++k) linear_value[srgb8_to_linear16(c[k])] = true;
    bool all_linear = true;
    for (draco::PointIndex p(0); p < d.num_points(); ++p) {
        std::array<std::uint16_t, 3> value;
        color->GetValue(color->mapped_index(p), value.data());
        for (int k = 0; k < 3; ++k) all_linear = all_linear && linear_value[value[k]];
    }
    CHECK(all_linear);

    test::TempDir dir;
    write_glb(mesh, dir.file("t.glb"), draco_node);
    CHECK(read_text(dir.file("t.glb")) == glb);
    check_round_trip(read_glb(dir.file("t.glb")), mesh, step);
}

TEST_CASE("draco: a mesh without colour stays without colour") {
    const Mesh mesh = torus_mesh(false);
    const double step = quantization_step(mesh, automatic_position_bits(mesh));
    check_round_trip(decode_draco(encode_draco(mesh, {}), "test"), mesh, step);
    test::TempDir dir;
    write_glb(mesh, dir.file("t.glb"), {});
    CHECK(test::glb_json(read_text(dir.file("t.glb"))).find("COLOR_0") == std::string::npos);
    check_round_trip(read_glb(dir.file("t.glb")), mesh, step);
}

TEST_CASE("draco: the same mesh gives the same bytes") {
    const Mesh mesh = torus_mesh();
    CHECK(encode_draco(mesh, {}) == encode_draco(torus_mesh(), {}));
    CHECK(encode_glb(mesh, {}) == encode_glb(torus_mesh(), {}));
    CHECK(encode_draco(mesh, {12, 7}) != encode_draco(mesh, {13, 7}));
}

TEST_CASE("draco: refusals") {
    test::TempDir dir;
    const Mesh empty;
    auto kind_of = [](auto&& action) {
        try {
            action();
        } catch (const Error& e) {
            return e.kind();
        }
        return ErrorKind{};
    };
    CHECK(kind_of([&] { write_draco(empty, dir.file("e.drc"), {}); }) == ErrorKind::output);
    CHECK(kind_of([&] { write_glb(empty, dir.file("e.glb"), {}); }) == ErrorKind::output);
    CHECK(!std::filesystem::exists(dir.file("e.drc")));
    CHECK(kind_of([&] { write_draco(torus_mesh(), dir.file("no/such/folder/t.drc"), {}); }) == ErrorKind::output);

    std::ofstream(dir.file("junk.drc")) << "not a draco file at all";
    CHECK(kind_of([&] { read_draco(dir.file("junk.drc")); }) == ErrorKind::input);
    CHECK(kind_of([&] { read_draco(dir.file("missing.drc")); }) == ErrorKind::input);
    write_draco(torus_mesh(), dir.file("t.drc"), {});
    CHECK(kind_of([&] { read_glb(dir.file("t.drc")); }) == ErrorKind::input);

    const std::string glb = encode_glb(torus_mesh(), {});
    std::ofstream(dir.file("cut.glb"), std::ios::binary) << glb.substr(0, glb.size() / 2);
    CHECK(kind_of([&] { read_glb(dir.file("cut.glb")); }) == ErrorKind::input);
    std::string bad_json = glb;
    bad_json.replace(bad_json.find("\"meshes\""), 8, "\"mashes\"");
    std::ofstream(dir.file("bad.glb"), std::ios::binary) << bad_json;
    CHECK(kind_of([&] { read_glb(dir.file("bad.glb")); }) == ErrorKind::input);
}
