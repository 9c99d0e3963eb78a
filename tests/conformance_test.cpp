// SPDX-License-Identifier: Apache-2.0
// Conformance on real LAS files from public projects (../shared/data/las), against facts measured
// by an independent reader (MANIFEST.tsv). Skipped with a message when the corpus is absent.
#include "lasmesh/error.hpp"
#include "lasmesh/las_reader.hpp"
#include "read/las_scan.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

using namespace lasmesh;

namespace {

using test::Row;

using test::read_manifest;
using test::split;

Vec3 parse_vec3(const std::string& text) {
    const std::vector<std::string> parts = split(text, ',');
    REQUIRE(parts.size() == 3);
    return {std::stod(parts[0]), std::stod(parts[1]), std::stod(parts[2])};
}

// Same formula (integer * scale + offset in doubles), so the values should agree to the last
// bit; allow a relative 1e-12 for a different order of operations.
void check_close(const Vec3& got, const Vec3& expected) {
    for (int a = 0; a < 3; ++a) CHECK(std::abs(got[a] - expected[a]) <= 1e-12 * std::max(1.0, std::abs(expected[a])));
}

} // namespace

TEST_CASE("real LAS files: info --scan agrees with the independently measured manifest" *
          doctest::test_suite("shared")) {
    const std::filesystem::path folder = test::shared_las_folder();
    REQUIRE_MESSAGE(!folder.empty(),
                    "../shared/data/las/MANIFEST.tsv is absent (the unit_shared test is skipped then)");
    const std::vector<Row> rows = read_manifest(folder);
    REQUIRE(rows.size() >= 30);
    int accepted = 0, refused = 0;
    for (const Row& row : rows) {
        const std::string path = (folder / row.at("file")).string();
        CAPTURE(path);
        const bool malformed = row.at("issues") != "none";
        if (malformed) {
            // Count mismatch, truncation, VLR overrun or an unknown version: refuse, naming the file.
            try {
                LasReader reader(path);
                scan_points(reader);
                FAIL("accepted a malformed file: " << row.at("issues"));
            } catch (const Error& e) {
                CHECK(e.kind() == ErrorKind::input);
                CHECK(std::string(e.what()).find(row.at("file")) != std::string::npos);
                ++refused;
            }
            continue;
        }
        LasReader reader(path);
        const LasHeader& h = reader.header();
        CHECK(version_string(h) == row.at("version"));
        CHECK(std::to_string(h.point_format) == row.at("point_format"));
        CHECK(std::to_string(h.point_record_length) == row.at("point_record_length"));
        CHECK(std::to_string(h.point_count) == row.at("header_point_count"));
        CHECK(std::to_string(h.offset_to_point_data) == row.at("offset_to_point_data"));
        CHECK(std::to_string(h.vlrs.size()) == row.at("num_vlrs"));
        CHECK(has_color(h) == (row.at("has_rgb_field") == "True"));
        check_close(h.scale, parse_vec3(row.at("scale")));
        check_close(h.min, parse_vec3(row.at("header_min")));
        check_close(h.max, parse_vec3(row.at("header_max")));

        const ScanResult scan = scan_points(reader, 4096);
        CHECK(std::to_string(scan.point_count) == row.at("points_present"));
        if (scan.point_count > 0) {
            check_close(scan.min, parse_vec3(row.at("actual_min")));
            check_close(scan.max, parse_vec3(row.at("actual_max")));
        }
        if (!row.at("rgb_min").empty()) {
            const Vec3 lo = parse_vec3(row.at("rgb_min")), hi = parse_vec3(row.at("rgb_max"));
            for (int c = 0; c < 3; ++c) {
                CHECK(scan.color_min[c] == lo[c]);
                CHECK(scan.color_max[c] == hi[c]);
            }
        }
        ++accepted;
    }
    MESSAGE(accepted << " files read as measured, " << refused << " malformed files refused");
    CHECK(refused == 5);
}
