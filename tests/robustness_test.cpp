// SPDX-License-Identifier: Apache-2.0
// Issue 19, "nothing lost, nothing silent": the library-level checks behind the command line's
// new refusals and warnings (tests/cli/errors_test.sh covers the command line itself).
#include "grid/auto_grid.hpp"
#include "io/output_file.hpp"
#include "io/ply_reader.hpp"
#include "io/same_file.hpp"
#include "lasmesh/compare.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/grid.hpp"
#include "lasmesh/las_reader.hpp"
#include "number_text.hpp"
#include "test_support.hpp"

#include <boost/iostreams/filter/gzip.hpp>
#include <doctest/doctest.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <unistd.h>

using namespace lasmesh;
using test::Bytes;

namespace {

Bytes sphere_las(std::uint64_t count) {
    lasgen::SceneOptions o;
    o.kind = lasgen::SceneKind::sphere;
    return test::make_las(lasgen::LasLayout{}, lasgen::make_scene(o), count);
}

Bytes gzip(const Bytes& plain) {
    return test::compress(plain, boost::iostreams::gzip_compressor());
}

std::uint64_t read_everything(LasReader& reader) {
    Bytes chunk(100 * reader.header().point_record_length);
    std::uint64_t records = 0;
    while (std::size_t n = reader.read_records(chunk)) records += n;
    return records;
}

} // namespace

TEST_CASE("records after the header's count are counted, in files and compressed streams") {
    test::TempDir dir;
    Bytes las = sphere_las(100);
    const std::uint32_t length = 34;
    las.insert(las.end(), las.end() - 3 * length - 5, las.end()); // 3 records and 5 bytes more
    test::write_file(dir.file("extra.las"), las);
    test::write_file(dir.file("extra.las.gz"), gzip(las));
    for (const char* name : {"extra.las", "extra.las.gz"}) {
        CAPTURE(name);
        LasReader reader(dir.file(name));
        CHECK(read_everything(reader) == 100);
        CHECK(reader.trailing_bytes() == 3 * length + 5);
        CHECK(trailing_warning(reader).find("107 bytes (3 whole records of 34 bytes) follow the 100 point records") !=
              std::string::npos);
    }
    test::write_file(dir.file("exact.las"), sphere_las(100));
    LasReader exact(dir.file("exact.las"));
    read_everything(exact);
    CHECK(trailing_warning(exact).empty());
}

TEST_CASE("a gzip trailer is verified even when the last record ends the reading") {
    test::TempDir dir;
    Bytes gz = gzip(sphere_las(100));
    gz[gz.size() - 8] ^= std::byte{0xFF}; // the CRC32
    test::write_file(dir.file("bad-crc.las.gz"), gz);
    LasReader reader(dir.file("bad-crc.las.gz"));
    CHECK_THROWS_WITH_AS(read_everything(reader), doctest::Contains("CRC mismatch"), Error);
}

TEST_CASE("output files: two open at once in one thread keep their own bytes") {
    // Each OutputFile has its own stdio buffer: a buffer shared per thread would mix the two.
    test::TempDir dir;
    lasmesh::OutputFile a(dir.file("a.bin")), b(dir.file("b.bin"));
    std::string bytes_a, bytes_b;
    for (int i = 0; i < 3000; ++i) { // 3 MB each: past the buffers several times
        const std::string line_a(1000, char('a' + i % 26)), line_b(1000, char('A' + i % 26));
        a.write(line_a), b.write(line_b);
        bytes_a += line_a, bytes_b += line_b;
    }
    a.commit();
    b.commit();
    const test::Bytes read_a = test::read_file(dir.file("a.bin")), read_b = test::read_file(dir.file("b.bin"));
    CHECK(std::string(reinterpret_cast<const char*>(read_a.data()), read_a.size()) == bytes_a);
    CHECK(std::string(reinterpret_cast<const char*>(read_b.data()), read_b.size()) == bytes_b);
}

TEST_CASE("output files: all or none, even when the second rename fails after the first") {
    test::TempDir dir;
    // The third output's final path is a folder with a file in it: its rename fails after the
    // first two succeeded, and those must go again.
    std::filesystem::create_directories(dir.path() / "c.ply" / "inside");
    std::vector<std::unique_ptr<OutputFile>> files;
    for (const char* name : {"a.ply", "b.ply", "c.ply"}) {
        files.push_back(std::make_unique<OutputFile>(dir.file(name)));
        files.back()->write(std::string("bytes of ") + name);
    }
    CHECK_THROWS_AS(commit_all(files), Error);
    CHECK(!std::filesystem::exists(dir.file("a.ply")));
    CHECK(!std::filesystem::exists(dir.file("b.ply")));
    CHECK(std::filesystem::is_directory(dir.file("c.ply")));
}

TEST_CASE("same_file: by inode for existing files, by folder and name for new ones") {
    test::TempDir dir;
    test::write_file(dir.file("a.las"), sphere_las(10));
    test::write_file(dir.file("b.las"), sphere_las(10));
    REQUIRE(::link(dir.file("a.las").c_str(), dir.file("hard.las").c_str()) == 0);
    CHECK(same_file(dir.file("a.las"), dir.file("a.las")));
    CHECK(same_file(dir.file("a.las"), (dir.path() / "." / "a.las").string()));
    CHECK(same_file(dir.file("a.las"), dir.file("hard.las")));
    CHECK_FALSE(same_file(dir.file("a.las"), dir.file("b.las")));
    CHECK(same_file(dir.file("new.ply"), (dir.path() / "." / "new.ply").string()));
    CHECK_FALSE(same_file(dir.file("new.ply"), dir.file("other.ply")));
    CHECK_FALSE(same_file(dir.file("a.las"), dir.file("new.ply")));

    CHECK_NOTHROW(
        check_distinct_files({{"the input", "-"}, {"-o", dir.file("x.ply")}, {"--report", dir.file("x.json")}}));
    try {
        check_distinct_files({{"the input", dir.file("a.las")}, {"-o", dir.file("hard.las")}});
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::usage);
        CHECK(std::string(e.what()).find("-o \"" + dir.file("hard.las") + "\" and the input \"" + dir.file("a.las") +
                                         "\" are the same file") != std::string::npos);
    }
}

TEST_CASE("cell starts along an axis: one-ulp bounds at a huge offset take no time") {
    // Offset 1e15 (one ulp: 0.125) and scale 1e-12: every raw value maps to 1e15 itself, so a
    // search walking from an estimate went through 2^31 raw values per cell face.
    GridSpec grid;
    grid.origin = {1e15, 1e15, 1e15};
    grid.cell_size = 0.125 / 16;
    grid.dims = {16, 16, 16};
    const double scale = 1e-12, offset = 1e15;
    const auto start = std::chrono::steady_clock::now();
    const AxisCells cells = axis_cells(grid, 0, scale, offset);
    CHECK(std::chrono::steady_clock::now() - start <
          std::chrono::seconds(10)); // microseconds here; a walk through 2^31 raw values a face, far longer
    REQUIRE(cells.starts.size() == 17);
    for (std::size_t i = 1; i < cells.starts.size(); ++i) CHECK(cells.starts[i - 1] <= cells.starts[i]);
    // Each start is the first raw value at or past its cell's lower face (or the int32 range's end).
    auto world = [&](std::int64_t raw) { return static_cast<double>(raw) * scale + offset; };
    for (std::uint32_t i = 0; i < 16; ++i) {
        const double face = grid.origin[0] + i * grid.cell_size;
        const std::int64_t s = cells.starts[i];
        if (s <= std::numeric_limits<std::int32_t>::max()) CHECK(world(s) >= face);
        if (s > std::numeric_limits<std::int32_t>::min()) CHECK_FALSE(world(s - 1) >= face);
    }
}

TEST_CASE("header bounds no record can reach are refused, naming the field") {
    LasHeader h;
    h.scale = {0.001, 0.001, 0.001};
    h.offset = {0, 0, 0};
    h.min = {-1, -1, -1};
    h.max = {1, 1, 1};
    CHECK_NOTHROW(check_header_bounds_usable(h, "x.las"));
    h.min[1] = -1e300, h.max[1] = 1e300;
    CHECK_THROWS_WITH_AS(check_header_bounds_usable(h, "x.las"),
                         doctest::Contains("header bounds min/max Y (bytes 195-210: -1e+300 to 1e+300) lie beyond"),
                         Error);
    h.scale = {1e300, 1e300, 1e300}; // reachable now, but wider than float positions
    CHECK_THROWS_WITH_AS(check_header_bounds_usable(h, "x.las"), doctest::Contains("float positions"), Error);
    GridRequest request;
    CHECK_THROWS_WITH_AS(make_grid_spec({{-1e308, 0, 0}, {1e308, 1, 1}}, request),
                         doctest::Contains("too wide to grid"), Error);
}

TEST_CASE("--grid auto: the cell from the density, clamped, and too few points refused") {
    // A flat 100 x 100 scan (area 100 * 100 + 100 * 0.5 = 10,050). Four million points: 12 a
    // cell (the most), a cell of sqrt(12 * 10050 / 4e6) = 0.1736: 576 cells.
    const GridChoice dense = choose_grid(4'000'000, {{0, 0, 0}, {100, 100, 0.5}}, "x.las");
    CHECK(dense.request.kind == GridRequest::Kind::longest_axis);
    CHECK(dense.request.dims[0] == 576);
    CHECK(dense.points_per_cell == 12);
    CHECK(dense.min_median == 4);
    CHECK(dense.reason.find("12 a cell: 576 cells") != std::string::npos);
    // A million: 100,000 surface cells at 10 a cell, sqrt(10 * 10050 / 1e6) = 0.3170: 315 cells.
    const GridChoice flat = choose_grid(1'000'000, {{0, 0, 0}, {100, 100, 0.5}}, "x.las");
    CHECK(flat.request.dims[0] == 315);
    CHECK(flat.points_per_cell == 10);
    CHECK(flat.min_median == 3);
    // 100,000: 3.5 a cell (the fewest), sqrt(3.5 * 10050 / 1e5) = 0.5931: 169 cells; coarsened
    // only below a median of 2.
    const GridChoice sparse = choose_grid(100'000, {{0, 0, 0}, {100, 100, 0.5}}, "x.las");
    CHECK(sparse.request.dims[0] == 169);
    CHECK(sparse.points_per_cell == 3.5);
    CHECK(sparse.min_median == 2);
    CHECK(choose_grid(300, {{0, 0, 0}, {100, 100, 1}}, "x.las").request.dims[0] == auto_grid_min_cells);
    CHECK(choose_grid(1'000'000'000'000, {{0, 0, 0}, {100, 100, 1}}, "x.las").request.dims[0] == auto_grid_max_cells);
    CHECK_THROWS_WITH_AS(choose_grid(99, {{0, 0, 0}, {1, 1, 1}}, "x.las"),
                         doctest::Contains("too few to outline a surface"), Error);
}

TEST_CASE("compare refuses what it cannot measure instead of printing numbers") {
    test::TempDir dir;
    test::write_file(dir.file("c.las"), sphere_las(100));
    Mesh empty;
    empty.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    LasReader cloud(dir.file("c.las"));
    CHECK_THROWS_WITH_AS(compare(empty, cloud, {}), doctest::Contains("no triangles"), Error);
    Mesh flat = empty;
    flat.positions[2] = {2, 0, 0};
    flat.triangles = {{0, 1, 2}};
    CHECK_THROWS_WITH_AS(compare(flat, cloud, {}), doctest::Contains("zero area"), Error);
}

TEST_CASE("PLY: counts beyond the file's size and non-finite origins are refused before use") {
    test::TempDir dir;
    auto write_text = [&](const std::string& text) {
        std::ofstream(dir.file("bad.ply"), std::ios::binary) << text;
        return dir.file("bad.ply");
    };
    CHECK_THROWS_WITH_AS(read_ply(write_text("ply\nformat binary_little_endian 1.0\nelement vertex 100000000\n"
                                             "property float x\nproperty float y\nproperty float z\nend_header\n")),
                         doctest::Contains("need at least 100000000 bytes, but only 0 follow"), Error);
    const std::string body = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
                             "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    CHECK_THROWS_WITH_AS(read_ply(write_text("ply\nformat ascii 1.0\ncomment origin nan 0 0\n" + body)),
                         doctest::Contains("three finite numbers"), Error);
    CHECK_THROWS_WITH_AS(read_ply(write_text("ply\nformat ascii 1.0\ncomment cell_size inf\n" + body)),
                         doctest::Contains("cell_size"), Error);
    CHECK(read_ply(write_text("ply\nformat ascii 1.0\ncomment origin 1 2 3\n" + body)).origin == Vec3{1, 2, 3});
}

TEST_CASE("numbers for people: significant digits, no exponent where none is needed") {
    CHECK(four_digits(0.11931221541867104) == "0.1193");
    CHECK(four_digits(0.05965610770933552) == "0.05966");
    CHECK(four_digits(977.5) == "977.5");
    CHECK(four_digits(0.5) == "0.5");
    CHECK(four_digits(3) == "3");
    CHECK(four_digits(-2.0599999999999996) == "-2.06");
    CHECK(significant(2362.4, 3) == "2360");
    CHECK(significant(796931, 3) == "797000");
    CHECK(four_digits(1e301) == "1e+301");
    CHECK(four_digits(1e-9) == "1e-09");
    // Coordinates: to the decimals of the step asked for, at least one.
    CHECK(coordinate(431249.90434389235, 0.1193 / 1000) == "431249.9043");
    CHECK(coordinate(-2.0599999999999996, 0.01) == "-2.06");
    CHECK(coordinate(6700199.889645642, 5.0) == "6700199.9");
}
