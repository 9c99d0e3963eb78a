// SPDX-License-Identifier: Apache-2.0
// Coordinate systems: read from GeoTIFF keys and WKT, named and measured by PROJ, refused in
// degrees, and recorded in every output format.
#include "byte_order.hpp"
#include "lasmesh/build_mesh.hpp"
#include "lasmesh/mesh_files.hpp"
#include "read/crs.hpp"
#include "read/las_header.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <cstring>

using namespace lasmesh;

namespace {

// A small deck scan declaring `epsg` in GeoTIFF keys (0: no CRS), at `origin`.
std::string deck_with_crs(const test::TempDir& dir, const std::string& name, int epsg, const Vec3& origin) {
    lasgen::SceneOptions scene;
    scene.origin = origin;
    lasgen::LasLayout layout;
    layout.epsg = epsg;
    const std::string path = dir.file(name);
    test::write_file(path, test::make_las(layout, lasgen::make_scene(scene), 40000, 3));
    return path;
}

LasHeader header_of(const std::string& path) {
    return LasReader(path).header();
}

OutputRequest output(const std::string& path) {
    OutputRequest request;
    request.path = path;
    return request;
}

// WKT 1 of WGS 84 / UTM zone 31N without AUTHORITY nodes: PROJ must find the code itself.
const std::string utm31n_wkt =
    "PROJCS[\"WGS 84 / UTM zone 31N\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,"
    "298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],PROJECTION["
    "\"Transverse_Mercator\"],PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\",3],"
    "PARAMETER[\"scale_factor\",0.9996],PARAMETER[\"false_easting\",500000],PARAMETER[\"false_northing\",0],"
    "UNIT[\"metre\",1],AXIS[\"Easting\",EAST],AXIS[\"Northing\",NORTH]]";

// A header holding one LASF_Projection VLR with `payload`.
LasHeader with_vlr(std::uint16_t record, const std::string& payload) {
    LasHeader header;
    Vlr vlr;
    vlr.user_id = "LASF_Projection";
    vlr.record_id = record;
    vlr.data.resize(payload.size());
    std::memcpy(vlr.data.data(), payload.data(), payload.size());
    header.vlrs.push_back(vlr);
    return header;
}

} // namespace

TEST_CASE("crs: GeoTIFF keys give the EPSG CRS, its name, kind and units (metres, feet, degrees)") {
    test::TempDir dir;
    const std::optional<CrsInfo> utm = read_crs(header_of(deck_with_crs(dir, "utm.las", 32631, {431250, 6700200, 10})));
    REQUIRE(utm);
    CHECK(utm->source == "GeoTIFF keys");
    CHECK(utm->name == "WGS 84 / UTM zone 31N");
    CHECK(utm->code == "EPSG:32631");
    CHECK(utm->kind == "projected");
    CHECK(utm->unit == "metre");
    CHECK(utm->unit_metres == 1.0);
    CHECK(utm->wkt.find("UTM zone 31N") != std::string::npos);
    CHECK(utm->wkt.find('\n') == std::string::npos); // one line, for a PLY comment

    const std::optional<CrsInfo> feet = read_crs(header_of(deck_with_crs(dir, "ft.las", 2992, {7600000, 700000, 100})));
    REQUIRE(feet);
    CHECK(feet->name == "NAD83 / Oregon GIC Lambert (ft)");
    CHECK(feet->unit == "foot");
    CHECK(feet->unit_metres == doctest::Approx(0.3048));
    CHECK(crs_summary(*feet).find("(EPSG:2992), projected, in foot (0.3048 m)") != std::string::npos);

    const std::optional<CrsInfo> degrees = read_crs(header_of(deck_with_crs(dir, "wgs84.las", 4326, {0, 0, 0})));
    REQUIRE(degrees);
    CHECK(degrees->geographic());
    CHECK(degrees->unit == "degree");

    CHECK_FALSE(read_crs(header_of(deck_with_crs(dir, "none.las", 0, {0, 0, 0}))));
}

TEST_CASE("crs: a WKT VLR is read, identified without an id, and a broken one is reported, not fatal") {
    const std::string wkt = utm31n_wkt;
    const std::optional<CrsInfo> read = read_crs(with_vlr(2112, wkt + std::string(1, '\0')));
    REQUIRE(read);
    CHECK(read->source == "OGC WKT");
    CHECK(read->code == "EPSG:32631");
    CHECK(read->kind == "projected");

    const std::optional<CrsInfo> broken = read_crs(with_vlr(2112, "PROJCS[\"half"));
    REQUIRE(broken);
    CHECK_FALSE(broken->identified());
    CHECK(broken->problem.find("unreadable") != std::string::npos);
    CHECK(crs_summary(*broken).find("not identified") != std::string::npos);
}

TEST_CASE("crs: a LAS 1.4 file's WKT in an extended VLR, after the points, is read from a file") {
    test::TempDir dir;
    lasgen::LasLayout layout;
    layout.version_minor = 4, layout.point_format = 7;
    lasgen::SceneOptions scene;
    scene.origin = {431250, 6700200, 10};
    test::Bytes las = test::make_las(layout, lasgen::make_scene(scene), 5000, 3);
    // EVLRs: another one first (skipped by its length), then the WKT, NUL-terminated.
    const auto evlr = [&](const std::string& user, std::uint16_t record, const std::string& payload) {
        test::Bytes head(60);
        std::memcpy(head.data() + 2, user.data(), user.size());
        store_le<std::uint16_t>(head.data() + 18, record);
        store_le<std::uint64_t>(head.data() + 20, payload.size());
        las.insert(las.end(), head.begin(), head.end());
        for (char c : payload) las.push_back(static_cast<std::byte>(c));
    };
    store_le<std::uint64_t>(las.data() + 235, las.size());
    store_le<std::uint32_t>(las.data() + 243, 2);
    evlr("pylastest", 42, std::string(1000, 'x'));
    evlr("LASF_Projection", 2112, utm31n_wkt + std::string(1, '\0'));
    const std::string path = dir.file("evlr.las");
    test::write_file(path, las);

    const LasHeader header = header_of(path);
    CHECK(header.evlr_count == 2);
    REQUIRE(header.crs_evlrs.size() == 1);
    const std::optional<CrsInfo> crs = read_crs(header);
    REQUIRE(crs);
    CHECK(crs->source == "OGC WKT");
    CHECK(crs->code == "EPSG:32631");
    // The first EVLR claims to reach past the end of the file: it and those after it are left
    // out, not read past the end.
    store_le<std::uint64_t>(las.data() + load_le<std::uint64_t>(las.data() + 235) + 20, std::uint64_t{1} << 40);
    test::write_file(path, las);
    CHECK(header_of(path).crs_evlrs.empty());
}

TEST_CASE("crs: a projected CRS is reported and recorded in every output") {
    test::TempDir dir;
    BuildOptions o;
    o.grid = GridRequest::longest(64);
    for (const char* name : {"m.ply", "m.drc", "m.glb"}) o.outputs.push_back(output(dir.file(name)));
    const BuildResult result = build_mesh(deck_with_crs(dir, "utm.las", 32631, {431250, 6700200, 10}), o);
    CHECK(result.report.crs_recorded == "EPSG:32631");
    CHECK(result.report.crs.find("WGS 84 / UTM zone 31N (EPSG:32631)") == 0);
    for (const char* name : {"m.ply", "m.drc", "m.glb"}) {
        CAPTURE(name);
        CHECK(read_mesh(dir.file(name)).crs == "EPSG:32631");
    }
    // Without a CRS nothing is recorded.
    BuildOptions plain;
    plain.grid = GridRequest::longest(64);
    plain.outputs.push_back(output(dir.file("p.ply")));
    CHECK(build_mesh(deck_with_crs(dir, "none.las", 0, {0, 0, 0}), plain).report.crs.empty());
    CHECK(read_mesh(dir.file("p.ply")).crs.empty());
}
