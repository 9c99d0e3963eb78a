// SPDX-License-Identifier: Apache-2.0
// LAZ decoding: real files from public projects, facts measured by an independent decoder
// (laz-perf) in a MANIFEST.tsv, SHA-256 of all records included: the small set in tests/data/laz,
// always, and the larger corpus beside the checkout (../shared/data/laz, the "shared" test suite,
// which CTest runs as unit_shared and reports Skipped without it); and robustness on truncated
// and damaged LAZ.
#include "byte_order.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/las_reader.hpp"
#include "read/input_stream.hpp"
#include "read/las_header.hpp"
#include "sha256.hpp"
#include "test_support.hpp"

#include <boost/iostreams/copy.hpp>
#include <boost/iostreams/filter/gzip.hpp>
#include <boost/iostreams/filtering_stream.hpp>
#include <doctest/doctest.h>

#include <algorithm>
#include <climits>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <variant>

using namespace lasmesh;

namespace {

using test::Row;

std::filesystem::path shared_laz_folder() {
    const char* override_dir = std::getenv("LASMESH_SHARED");
    const std::filesystem::path shared = override_dir
                                             ? std::filesystem::path(override_dir)
                                             : std::filesystem::path(LASMESH_SOURCE_DIR).parent_path() / "shared";
    const std::filesystem::path folder = shared / "data" / "laz";
    return std::filesystem::exists(folder / "MANIFEST.tsv") ? folder : std::filesystem::path();
}

// The small real LAZ files in the repository (tests/data/laz, facts in its MANIFEST.tsv).
std::filesystem::path repository_laz_folder() {
    return std::filesystem::path(LASMESH_SOURCE_DIR) / "tests" / "data" / "laz";
}

using test::read_manifest;
using test::split;

std::string join3(const std::array<std::int64_t, 3>& v) {
    return std::to_string(v[0]) + "," + std::to_string(v[1]) + "," + std::to_string(v[2]);
}

struct Decoded {
    std::uint64_t count = 0;
    std::string sha256;
    std::array<std::int64_t, 3> min_raw{INT64_MAX, INT64_MAX, INT64_MAX}, max_raw{INT64_MIN, INT64_MIN, INT64_MIN};
    std::array<std::int64_t, 3> rgb_min{INT64_MAX, INT64_MAX, INT64_MAX}, rgb_max{INT64_MIN, INT64_MIN, INT64_MIN};
    std::int64_t nir_min = INT64_MAX, nir_max = INT64_MIN;
};

Decoded decode_all(LasReader& reader) {
    const LasHeader& h = reader.header();
    const std::size_t length = h.point_record_length;
    std::vector<std::byte> buffer(length * 5000);
    test::Sha256 sha;
    Decoded d;
    const int rgb = rgb_offset(h.point_format);
    const bool nir = h.point_format == 8 || h.point_format == 10;
    while (std::size_t n = reader.read_records(buffer)) {
        sha.add(std::span(buffer.data(), n * length));
        for (std::size_t i = 0; i < n; ++i) {
            const std::byte* r = buffer.data() + i * length;
            for (int a = 0; a < 3; ++a) {
                const std::int64_t v = load_le<std::int32_t>(r + 4 * a);
                d.min_raw[a] = std::min(d.min_raw[a], v);
                d.max_raw[a] = std::max(d.max_raw[a], v);
                if (rgb >= 0) {
                    const std::int64_t c = load_le<std::uint16_t>(r + rgb + 2 * a);
                    d.rgb_min[a] = std::min(d.rgb_min[a], c);
                    d.rgb_max[a] = std::max(d.rgb_max[a], c);
                }
            }
            if (nir) {
                const std::int64_t v = load_le<std::uint16_t>(r + 36);
                d.nir_min = std::min(d.nir_min, v);
                d.nir_max = std::max(d.nir_max, v);
            }
        }
        d.count += n;
    }
    d.sha256 = sha.hex();
    return d;
}

} // namespace

TEST_CASE("sha256 of known inputs") {
    test::Sha256 empty;
    CHECK(empty.hex() == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    test::Sha256 abc;
    const std::string text = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    abc.add(std::as_bytes(std::span(text.data(), text.size())));
    CHECK(abc.hex() == "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST_CASE("real LAZ files decode to the independently measured records (SHA-256)" * doctest::test_suite("shared")) {
    const std::filesystem::path folder = shared_laz_folder();
    REQUIRE_MESSAGE(!folder.empty(),
                    "../shared/data/laz/MANIFEST.tsv is absent (the unit_shared test is skipped then)");
    const std::vector<Row> rows = read_manifest(folder);
    REQUIRE(rows.size() >= 14);
    int matched = 0, refused = 0, unverified = 0;
    for (const Row& row : rows) {
        if (row.at("file").ends_with(".las")) continue;
        const std::string path = (folder / row.at("file")).string();
        CAPTURE(path);
        if (row.at("decoder") == "header-only") {
            // Nobody decoded these independently: their header facts must hold (read without
            // the decoder), then decode them or refuse them, naming the file.
            {
                InputStream in(path);
                const LasHeader h = read_las_header(in);
                CHECK(h.compressed);
                CHECK(std::to_string(h.point_format) == row.at("point_format"));
                CHECK(std::to_string(h.point_record_length) == row.at("point_record_length"));
                CHECK(std::to_string(h.point_count) == row.at("header_point_count"));
                CHECK(std::to_string(h.vlrs.size()) == row.at("num_vlrs"));
                // The twin (a path from the folder holding shared/) has the same header facts.
                const std::filesystem::path twin =
                    folder.parent_path().parent_path().parent_path() / row.at("twin_file");
                if (row.at("twin_file") != "-" && std::filesystem::exists(twin)) {
                    LasReader other(twin.string());
                    CHECK(other.header().point_count == h.point_count);
                    CHECK(other.header().point_format == h.point_format);
                    CHECK(other.header().scale == h.scale);
                    CHECK(other.header().offset == h.offset);
                    CHECK(other.header().min == h.min);
                    CHECK(other.header().max == h.max);
                }
            }
            try {
                LasReader reader(path);
                CHECK(std::to_string(reader.header().point_count) == row.at("header_point_count"));
                const Decoded d = decode_all(reader);
                CHECK(std::to_string(d.count) == row.at("header_point_count"));
                ++unverified;
            } catch (const Error& e) {
                CHECK(e.kind() == ErrorKind::input);
                CHECK(std::string(e.what()).find(row.at("file")) != std::string::npos);
                MESSAGE("refused: " << std::string(e.what()));
                ++refused;
            }
            continue;
        }
        LasReader reader(path);
        const LasHeader& h = reader.header();
        CHECK(h.compressed);
        CHECK(std::to_string(h.point_format) == row.at("point_format"));
        CHECK(std::to_string(h.point_record_length) == row.at("point_record_length"));
        CHECK(std::to_string(h.point_count) == row.at("header_point_count"));
        CHECK(std::to_string(h.offset_to_point_data) == row.at("offset_to_point_data"));
        CHECK(std::to_string(h.vlrs.size()) == row.at("num_vlrs"));
        const Decoded d = decode_all(reader);
        CHECK(std::to_string(d.count) == row.at("decoded_point_count"));
        CHECK(join3(d.min_raw) == row.at("actual_min_raw"));
        CHECK(join3(d.max_raw) == row.at("actual_max_raw"));
        CHECK(d.sha256 == row.at("points_sha256"));
        if (row.at("rgb_min") != "-") {
            CHECK(join3(d.rgb_min) == row.at("rgb_min"));
            CHECK(join3(d.rgb_max) == row.at("rgb_max"));
        }
        if (row.at("nir_min") != "-") {
            CHECK(std::to_string(d.nir_min) == row.at("nir_min"));
            CHECK(std::to_string(d.nir_max) == row.at("nir_max"));
        }
        if (d.sha256 == row.at("points_sha256")) ++matched;
    }
    MESSAGE(matched << " LAZ files match their SHA-256, " << unverified << " unverifiable decoded, " << refused
                    << " refused");
    CHECK(matched == 12); // every file decoded independently
}

namespace {

test::Bytes gzip(const test::Bytes& plain) {
    std::string input(reinterpret_cast<const char*>(plain.data()), plain.size());
    std::istringstream source(input);
    std::ostringstream sink;
    boost::iostreams::filtering_ostream out;
    out.push(boost::iostreams::gzip_compressor());
    out.push(sink);
    boost::iostreams::copy(source, out);
    const std::string text = sink.str();
    const auto* p = reinterpret_cast<const std::byte*>(text.data());
    return test::Bytes(p, p + text.size());
}

// All records of `path`, or the input error's message (which must name the file).
std::variant<test::Bytes, std::string> decode_or_error(const std::string& path) {
    try {
        LasReader reader(path);
        const std::size_t length = reader.header().point_record_length;
        test::Bytes all, buffer(length * 700);
        while (std::size_t n = reader.read_records(buffer))
            all.insert(all.end(), buffer.begin(), buffer.begin() + n * length);
        return all;
    } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::input);
        const std::string message = e.what();
        CHECK(message.find(path) != std::string::npos);
        CHECK(message.find('\n') == std::string::npos);
        return message;
    }
}

} // namespace

TEST_CASE("every truncation and many damaged bytes of a LAZ file give a clean error or the exact records") {
    const std::filesystem::path folder = repository_laz_folder();
    test::TempDir dir;
    // Pointwise (compressor 2) and layered (compressor 3): from a file (chunk table) and from
    // a gzip stream (no table: sequential decoding).
    for (const char* name : {"laspy_simple.laz", "laspy_1_4_w_evlr.laz"}) {
        CAPTURE(name);
        const test::Bytes file = test::read_file((folder / name).string());
        const auto full = decode_or_error((folder / name).string());
        REQUIRE(std::holds_alternative<test::Bytes>(full));
        const test::Bytes& records = std::get<test::Bytes>(full);
        int errors = 0;
        for (std::size_t size = 0; size < file.size(); size += size < 400 ? 1 : 127) {
            CAPTURE(size);
            const test::Bytes prefix(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(size));
            test::write_file(dir.file("cut.laz"), prefix);
            const auto plain = decode_or_error(dir.file("cut.laz"));
            if (std::holds_alternative<test::Bytes>(plain))
                CHECK(std::get<test::Bytes>(plain) == records);
            else
                ++errors;
            test::write_file(dir.file("cut.laz.gz"), gzip(prefix));
            const auto piped = decode_or_error(dir.file("cut.laz.gz"));
            if (std::holds_alternative<test::Bytes>(piped)) CHECK(std::get<test::Bytes>(piped) == records);
        }
        CHECK(errors > 400);
        // Damage: one byte changed at a time in the points and the chunk table; any outcome but
        // a crash or a hang is acceptable (the sanitizer build checks the memory accesses).
        const std::size_t points_at = load_le<std::uint32_t>(file.data() + 96);
        for (std::size_t at = points_at; at < file.size(); at += 101) {
            test::Bytes bad = file;
            bad[at] ^= std::byte{0x5A};
            test::write_file(dir.file("bad.laz"), bad);
            (void)decode_or_error(dir.file("bad.laz"));
        }
    }
}

TEST_CASE("the repository's LAZ files decode to the independently measured records (SHA-256)") {
    // Point formats 1, 3, 6, 7 and 8; compressors 2 and 3; fixed and variable chunks; COPC.
    const std::filesystem::path folder = repository_laz_folder();
    const std::vector<Row> rows = read_manifest(folder);
    REQUIRE(rows.size() == 8);
    std::set<int> formats;
    int matched = 0;
    for (const Row& row : rows) {
        const std::string path = (folder / row.at("file")).string();
        CAPTURE(path);
        LasReader reader(path);
        const LasHeader& h = reader.header();
        CHECK(h.compressed);
        CHECK(std::to_string(h.point_format) == row.at("point_format"));
        CHECK(std::to_string(h.point_record_length) == row.at("record_length"));
        CHECK(std::to_string(h.point_count) == row.at("point_count"));
        formats.insert(h.point_format);
        const Decoded d = decode_all(reader);
        CHECK(std::to_string(d.count) == row.at("point_count"));
        CHECK(join3(d.min_raw) == row.at("min_raw"));
        CHECK(join3(d.max_raw) == row.at("max_raw"));
        CHECK(d.sha256 == row.at("points_sha256"));
        if (row.at("rgb_min") != "-") {
            CHECK(join3(d.rgb_min) == row.at("rgb_min"));
            CHECK(join3(d.rgb_max) == row.at("rgb_max"));
        }
        // The same records through a gzip stream: no chunk table, decoded in sequence.
        test::TempDir dir;
        test::write_file(dir.file("f.laz.gz"), gzip(test::read_file(path)));
        LasReader piped(dir.file("f.laz.gz"));
        CHECK(decode_all(piped).sha256 == row.at("points_sha256"));
        matched += d.sha256 == row.at("points_sha256");
    }
    CHECK(formats == std::set<int>{1, 3, 6, 7, 8});
    CHECK(matched == 8);
}

TEST_CASE("LAZ without points, and LAZ whose chunks hold more points than the header counts") {
    const std::filesystem::path folder = repository_laz_folder();
    const test::Bytes simple = test::read_file((folder / "laspy_simple.laz").string());
    const std::size_t points_at = load_le<std::uint32_t>(simple.data() + 96);
    test::TempDir dir;
    SUBCASE("no points: no chunk table at all (LASzip's empty file), or one of no chunks; a file and a pipe alike") {
        for (const bool with_table : {false, true}) {
            CAPTURE(with_table);
            test::Bytes empty(simple.begin(), simple.begin() + static_cast<std::ptrdiff_t>(points_at) + 8);
            store_le<std::uint32_t>(empty.data() + 107, 0);
            store_le<std::int64_t>(empty.data() + points_at,
                                   static_cast<std::int64_t>(empty.size())); // the table: here
            if (with_table) empty.resize(empty.size() + 8, std::byte{0});    // version 0, 0 chunks
            test::write_file(dir.file("empty.laz"), empty);
            LasReader from_file(dir.file("empty.laz"));
            CHECK(from_file.header().point_count == 0);
            std::vector<std::byte> buffer(1000);
            CHECK(from_file.read_records(buffer) == 0);
            test::write_file(dir.file("empty.laz.gz"), gzip(empty));
            LasReader from_pipe(dir.file("empty.laz.gz"));
            CHECK(from_pipe.read_records(buffer) == 0);
        }
    }
    SUBCASE("more points in the chunks than the header counts: the header's count is read, and a warning says so") {
        // COPC: 65 variable chunks holding 1,065 points, the header (64-bit count) saying 1,000.
        const std::string copc = (folder / "laspy_simple.copc.laz").string();
        test::Bytes patched = test::read_file(copc);
        REQUIRE(load_le<std::uint64_t>(patched.data() + 247) == 1065);
        store_le<std::uint64_t>(patched.data() + 247, 1000);
        if (load_le<std::uint32_t>(patched.data() + 107) != 0)
            store_le<std::uint32_t>(patched.data() + 107, 1000); // kept equal
        test::write_file(dir.file("low.laz"), patched);
        LasReader full(copc), low(dir.file("low.laz"));
        const std::size_t length = full.header().point_record_length;
        std::vector<std::byte> all(1065 * length), first(1065 * length);
        REQUIRE(full.read_records(all) == 1065);
        REQUIRE(low.read_records(first) == 1000);
        CHECK(std::equal(first.begin(), first.begin() + static_cast<std::ptrdiff_t>(1000 * length), all.begin()));
        const std::string warning = trailing_warning(low);
        CAPTURE(warning);
        CHECK(warning.find("65 more points after the 1000 points the header counts") != std::string::npos);
        CHECK(warning.find("low.laz") != std::string::npos);
        CHECK(trailing_warning(full).empty());
    }
}
