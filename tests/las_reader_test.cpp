// SPDX-License-Identifier: Apache-2.0
// The streaming reader: every version x format the generator writes, chunking, compressed input,
// and the errors for truncated, LAZ, foreign and empty input.
#include "byte_order.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/las_reader.hpp"
#include "read/input_stream.hpp"
#include "read/las_point.hpp"
#include "read/las_scan.hpp"
#include "test_support.hpp"

#include <boost/iostreams/filter/bzip2.hpp>
#include <boost/iostreams/filter/gzip.hpp>
#include <boost/iostreams/filter/lzma.hpp>
#include <boost/iostreams/filter/zstd.hpp>
#include <doctest/doctest.h>

#include <cmath>
#include <sstream>

using namespace lasmesh;
using test::Bytes;

namespace {

lasgen::Scene small_sphere() {
    lasgen::SceneOptions o;
    o.kind = lasgen::SceneKind::sphere;
    o.size = 4;
    o.origin = {1000, 2000, 30};
    return lasgen::make_scene(o);
}

// All records of a file, read in chunks of `chunk` records.
Bytes read_all_records(const std::string& path, std::size_t chunk) {
    LasReader reader(path);
    Bytes all, buffer(chunk * reader.header().point_record_length);
    while (std::size_t n = reader.read_records(buffer))
        all.insert(all.end(), buffer.begin(), buffer.begin() + n * reader.header().point_record_length);
    CHECK(reader.records_left() == 0);
    return all;
}

// Runs the reader over a whole file and returns the message of the Error it must throw.
std::string input_error_of(const std::string& path) {
    try {
        LasReader reader(path);
        scan_points(reader, 7);
    } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::input);
        return e.what();
    }
    FAIL("no error for " << path);
    return {};
}

} // namespace

TEST_CASE("every LAS version and point format the generator writes reads back exactly") {
    test::TempDir dir;
    const lasgen::Scene scene = small_sphere();
    for (int minor = 0; minor <= 4; ++minor) {
        for (int format = 0; format <= 10; ++format) {
            lasgen::LasLayout layout;
            layout.version_minor = minor;
            layout.point_format = format;
            layout.extra_bytes = format % 3; // records longer than the core must be honoured
            layout.color_bits = format % 2 ? 16 : 8;
            try {
                lasgen::validate_layout(layout);
            } catch (const std::invalid_argument&) {
                continue; // a combination the specification does not allow
            }
            CAPTURE(minor);
            CAPTURE(format);
            const std::uint64_t count = 257;
            const std::string path = dir.file("v" + std::to_string(minor) + "f" + std::to_string(format) + ".las");
            test::write_file(path, test::make_las(layout, scene, count));

            LasReader reader(path);
            const LasHeader& h = reader.header();
            CHECK(int(h.version_minor) == minor);
            CHECK(int(h.point_format) == format);
            CHECK(h.point_record_length == core_record_size(format) + layout.extra_bytes);
            CHECK(h.point_count == count);
            CHECK(h.legacy_point_count == (format < 6 ? count : 0));
            CHECK(h.header_size == minimum_header_size(minor));
            REQUIRE(h.vlrs.size() == 1);
            CHECK(h.vlrs[0].user_id == "lasmesh");
            CHECK(h.vlrs[0].description == "lasgen scene");
            CHECK(h.scale == Vec3{0.001, 0.001, 0.001});
            CHECK(has_color(h) ==
                  (format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10));

            // Every record decodes to the generated point, within half a quantisation step.
            const PointDecoder decoder(h);
            Bytes records(count * h.point_record_length);
            REQUIRE(reader.read_records(records) == count);
            CHECK(reader.read_records(records) == 0);
            for (std::uint64_t i = 0; i < count; ++i) {
                const auto expected = lasgen::generate_point(scene, 1, i);
                const Vec3 got = decoder.position(records.data() + i * h.point_record_length);
                for (int a = 0; a < 3; ++a) REQUIRE(std::abs(got[a] - expected.position[a]) <= 0.0005 + 1e-9);
                if (decoder.has_color()) {
                    const Rgb16 c = decoder.color(records.data() + i * h.point_record_length);
                    for (int k = 0; k < 3; ++k)
                        REQUIRE(c[k] == (layout.color_bits == 16 ? expected.color[k] * 257 : expected.color[k]));
                }
            }
        }
    }
}

TEST_CASE("chunk size does not change the records: 1, 7, 1000 and all at once") {
    test::TempDir dir;
    const std::string path = dir.file("chunks.las");
    lasgen::LasLayout layout;
    test::write_file(path, test::make_las(layout, small_sphere(), 2503)); // prime: uneven last chunk
    const Bytes whole = read_all_records(path, 2503);
    CHECK(whole.size() == 2503u * 34);
    for (std::size_t chunk : {1u, 7u, 1000u, 5000u}) {
        CAPTURE(chunk);
        CHECK(read_all_records(path, chunk) == whole);
    }
}

TEST_CASE("gzip, bzip2, xz and zstd input give the same records as the plain file") {
    namespace io = boost::iostreams;
    test::TempDir dir;
    lasgen::LasLayout layout;
    layout.version_minor = 4;
    layout.point_format = 7;
    const Bytes plain = test::make_las(layout, small_sphere(), 40000); // > 1 MB: many decoder buffers
    test::write_file(dir.file("plain.las"), plain);
    const Bytes expected = read_all_records(dir.file("plain.las"), 4096);

    const std::pair<const char*, Bytes> variants[] = {
        {"gzip", test::compress(plain, io::gzip_compressor())},
        {"bzip2", test::compress(plain, io::bzip2_compressor())},
        {"xz", test::compress(plain, io::lzma_compressor())},
        {"zstd", test::compress(plain, io::zstd_compressor())},
    };
    for (const auto& [name, bytes] : variants) {
        CAPTURE(name);
        // A misleading name on purpose: detection goes by content, not by extension.
        const std::string path = dir.file(std::string(name) + ".las");
        test::write_file(path, bytes);
        CHECK(InputStream(path).compression() != Compression::none);
        CHECK(compression_name(InputStream(path).compression()) == name);
        CHECK(read_all_records(path, 999) == expected);
    }
}

TEST_CASE("every truncation of a small file gives a clean error, never a wrong result") {
    test::TempDir dir;
    lasgen::LasLayout layout;
    const Bytes full = test::make_las(layout, small_sphere(), 5);
    const std::string path = dir.file("cut.las");
    for (std::size_t size = 0; size < full.size(); ++size) {
        CAPTURE(size);
        test::write_file(path, Bytes(full.begin(), full.begin() + size));
        const std::string message = input_error_of(path);
        CHECK(message.find(path) != std::string::npos);
        if (size > full.size() - 5 * 34) { // inside the point records: say how many were read
            CHECK(message.find("whole point records") != std::string::npos);
            CHECK(message.find("promises 5 records") != std::string::npos);
        }
    }
    test::write_file(path, full);
    LasReader reader(path);
    CHECK(scan_points(reader).point_count == 5);
}

TEST_CASE("every truncation of a gzip stream gives a clean error or the exact records") {
    namespace io = boost::iostreams;
    test::TempDir dir;
    lasgen::LasLayout layout;
    const Bytes plain = test::make_las(layout, small_sphere(), 50);
    test::write_file(dir.file("plain.las"), plain);
    const Bytes expected = read_all_records(dir.file("plain.las"), 50);
    const Bytes gz = test::compress(plain, io::gzip_compressor());
    const std::string path = dir.file("cut.las.gz");
    int errors = 0;
    for (std::size_t size = 1; size < gz.size(); ++size) {
        CAPTURE(size);
        test::write_file(path, Bytes(gz.begin(), gz.begin() + size));
        try {
            const Bytes got = read_all_records(path, 7);
            CHECK(got == expected);
        } catch (const Error& e) {
            CHECK(e.kind() == ErrorKind::input);
            ++errors;
        }
    }
    CHECK(errors > 0);
}

TEST_CASE("foreign, empty and malformed LAZ input are refused with a message that says why") {
    test::TempDir dir;
    lasgen::LasLayout layout;
    const Bytes good = test::make_las(layout, small_sphere(), 3);

    SUBCASE("wrong signature") {
        Bytes bad = good;
        bad[0] = std::byte{'X'};
        test::write_file(dir.file("sig.las"), bad);
        CHECK(input_error_of(dir.file("sig.las")).find("expected the signature \"LASF\"") != std::string::npos);
    }
    SUBCASE("empty file") {
        test::write_file(dir.file("empty.las"), {});
        CHECK(input_error_of(dir.file("empty.las")).find("is empty") != std::string::npos);
    }
    SUBCASE("garbage") {
        Bytes noise(5000);
        for (std::size_t i = 0; i < noise.size(); ++i) noise[i] = static_cast<std::byte>((i * 7919) >> 3);
        test::write_file(dir.file("noise.las"), noise);
        CHECK(input_error_of(dir.file("noise.las")).find("is not a LAS file") != std::string::npos);
    }
    SUBCASE("LAZ compression bit without a LASzip VLR") {
        Bytes laz = good;
        laz[104] = std::byte{0x83};
        test::write_file(dir.file("a.laz"), laz);
        const std::string message = input_error_of(dir.file("a.laz"));
        CHECK(message.find("compression bits set, but there is no LASzip VLR") != std::string::npos);
    }
    SUBCASE("LAZ by the LASzip VLR") {
        Bytes laz = good;
        std::byte* vlr = laz.data() + 227;
        std::memset(vlr + 2, 0, 16);
        std::memcpy(vlr + 2, "laszip encoded", 14);
        store_le<std::uint16_t>(vlr + 18, 22204);
        test::write_file(dir.file("b.las"), laz);
        CHECK(input_error_of(dir.file("b.las")).find("LASzip VLR") != std::string::npos);
    }
    SUBCASE("unsupported version") {
        Bytes bad = good;
        bad[25] = std::byte{5};
        test::write_file(dir.file("v15.las"), bad);
        CHECK(input_error_of(dir.file("v15.las")).find("LAS version 1.5") != std::string::npos);
    }
    SUBCASE("point format above 10") {
        Bytes bad = good;
        bad[104] = std::byte{11};
        test::write_file(dir.file("f11.las"), bad);
        CHECK(input_error_of(dir.file("f11.las")).find("point data format 11") != std::string::npos);
    }
    SUBCASE("record length shorter than the format's core") {
        Bytes bad = good;
        store_le<std::uint16_t>(bad.data() + 105, 20);
        test::write_file(dir.file("short.las"), bad);
        CHECK(input_error_of(dir.file("short.las")).find("shorter than the 34 bytes") != std::string::npos);
    }
    SUBCASE("zero and non-finite scale factors") {
        Bytes bad = good;
        store_le<double>(bad.data() + 139, 0.0);
        test::write_file(dir.file("scale0.las"), bad);
        CHECK(input_error_of(dir.file("scale0.las")).find("Y scale factor at byte 139 is zero") != std::string::npos);
        store_le<double>(bad.data() + 139, std::nan(""));
        test::write_file(dir.file("scalenan.las"), bad);
        CHECK(input_error_of(dir.file("scalenan.las")).find("not a finite number") != std::string::npos);
    }
    SUBCASE("header size and offset to point data inconsistent") {
        Bytes bad = good;
        store_le<std::uint16_t>(bad.data() + 94, 200);
        test::write_file(dir.file("hsize.las"), bad);
        CHECK(input_error_of(dir.file("hsize.las")).find("header size 200") != std::string::npos);
        bad = good;
        store_le<std::uint32_t>(bad.data() + 96, 100);
        test::write_file(dir.file("offset.las"), bad);
        CHECK(input_error_of(dir.file("offset.las")).find("offset to point data 100") != std::string::npos);
    }
    SUBCASE("VLR running past the point data") {
        Bytes bad = good;
        store_le<std::uint16_t>(bad.data() + 227 + 20, 5000);
        test::write_file(dir.file("vlr.las"), bad);
        CHECK(input_error_of(dir.file("vlr.las")).find("runs past the offset to point data") != std::string::npos);
        bad = good;
        store_le<std::uint32_t>(bad.data() + 100, 1'000'000'000); // a count no file could hold
        test::write_file(dir.file("vlrcount.las"), bad);
        CHECK(input_error_of(dir.file("vlrcount.las")).find("VLR count (byte 100) is wrong") != std::string::npos);
    }
    SUBCASE("inverted header bounds") {
        Bytes bad = good;
        store_le<double>(bad.data() + 179, -1e9); // max X below min X
        test::write_file(dir.file("bounds.las"), bad);
        CHECK(input_error_of(dir.file("bounds.las")).find("header bounds are inverted") != std::string::npos);
    }
    SUBCASE("a directory and a missing file") {
        CHECK(input_error_of(dir.path().string()).find("is a directory") != std::string::npos);
        CHECK(input_error_of(dir.file("missing.las")).find("No such file") != std::string::npos);
    }
    SUBCASE("a corrupt zstd stream") {
        Bytes z = test::compress(good, boost::iostreams::zstd_compressor());
        for (std::size_t i = 8; i < z.size(); ++i) z[i] ^= std::byte{0x5A};
        test::write_file(dir.file("bad.zst"), z);
        CHECK(input_error_of(dir.file("bad.zst")).find("corrupt or truncated zstd stream") != std::string::npos);
    }
}

TEST_CASE("scan finds the bounds and colour range of the records themselves") {
    test::TempDir dir;
    lasgen::LasLayout layout;
    layout.color_bits = 16;
    const lasgen::Scene scene = small_sphere();
    test::write_file(dir.file("s.las"), test::make_las(layout, scene, 3000));
    LasReader reader(dir.file("s.las"));
    const ScanResult scan = scan_points(reader, 100);
    CHECK(scan.point_count == 3000);
    for (int a = 0; a < 3; ++a) {
        // A 2 m sphere sampled 3000 times reaches within a few centimetres of its extremes.
        CHECK(std::abs(scan.min[a] - (scene.origin[a] - 2)) < 0.05);
        CHECK(std::abs(scan.max[a] - (scene.origin[a] + 2)) < 0.05);
        CHECK(scan.min[a] >= reader.header().min[a]);
        CHECK(scan.max[a] <= reader.header().max[a]);
    }
    CHECK(scan.color_min == Rgb16{200 * 257, 80 * 257, 40 * 257});
    CHECK(scan.color_max == Rgb16{200 * 257, 80 * 257, 40 * 257});
}

TEST_CASE("read_points: every record's position (scale and offset applied) and stored colour, in order") {
    test::TempDir dir;
    std::vector<lasgen::GeneratedPoint> points;
    for (int i = 0; i < 70000; ++i) // more than one internal chunk of 65536 records
        points.push_back({{0.01 * (i % 300), 0.02 * (i % 170), 0.5 + 0.01 * (i % 7)},
                          {std::uint8_t(i % 251), std::uint8_t(i % 13), std::uint8_t(255 - i % 200)},
                          1});
    test::write_file(dir.file("p.las"), test::las_with_points(points, {0, 0, 0}, {3, 3.4, 0.6}));
    LasReader reader(dir.file("p.las"));
    std::vector<LasPoint> got(50000); // a buffer smaller than the file: two calls, then 0
    std::size_t i = 0;
    while (const std::size_t n = read_points(reader, got)) {
        for (std::size_t k = 0; k < n; ++k, ++i) {
            CAPTURE(i);
            for (int a = 0; a < 3; ++a) REQUIRE(std::abs(got[k].position[a] - points[i].position[a]) < 0.005 + 1e-9);
            for (int c = 0; c < 3; ++c) REQUIRE(got[k].color[c] == points[i].color[c]); // 8-bit values as stored
        }
    }
    CHECK(i == points.size());
    CHECK(read_points(reader, got) == 0);
}
