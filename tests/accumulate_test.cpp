// Accumulation on the OpenCL device (PoCL in CI) against hand-worked cases and a plain reference
// written here, for every slicing, colour depth and grid edge case.
#include "lasmesh/grid/density_grid.hpp"
#include "lasmesh/error.hpp"
#include "cli/option_parsing.hpp" // the option text parsers, from the command line
#include "lasmesh/read/las_point.hpp"
#include "grid/opencl_device.hpp" // internal: build_program
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace lasmesh;
using namespace lasmesh::cli;
using test::Bytes;

namespace {

ComputeDevice& device() {
    static ComputeDevice shared("auto"); // one context for the whole test run
    return shared;
}

// A LAS 1.2 format-3 file (format 1 without colour) holding exactly `points`.
Bytes las_with_points(const std::vector<lasgen::GeneratedPoint>& points, const Vec3& min, const Vec3& max,
                      int color_bits = 8, int format = 3, double scale = 0.01) {
    lasgen::LasLayout layout;
    layout.point_format = format;
    layout.color_bits = color_bits;
    layout.scale = {scale, scale, scale};
    Bytes file = lasgen::las_file_head(layout, points.size(), min, max, "fixture");
    const std::size_t head = file.size(), length = lasgen::record_length(layout);
    file.resize(head + points.size() * length);
    for (std::size_t i = 0; i < points.size(); ++i) lasgen::encode_record(layout, points[i], i, file.data() + head + i * length);
    return file;
}

DensityGrid accumulate_file(const std::string& path, AccumulateOptions options = {}) {
    LasReader reader(path);
    return accumulate_density(reader, device(), options);
}

AccumulateOptions grid_of(const std::string& text) {
    AccumulateOptions o;
    o.grid = parse_grid_request(text);
    return o;
}

// The reference: decode every point on the host and find its cell by the documented rule (the
// largest i with x >= origin + i * cell; the last cell closed at the top), in plain loops.
struct Reference {
    std::vector<std::uint64_t> count, red, green, blue;
    std::uint64_t outside = 0;
};

Reference reference_grid(const std::string& path, const GridSpec& g) {
    LasReader reader(path);
    const PointDecoder decoder(reader.header());
    Reference ref;
    ref.count.assign(g.cell_count(), 0);
    ref.red = ref.green = ref.blue = ref.count;
    Bytes records(reader.header().point_count * decoder.record_length + 1);
    const std::size_t n = reader.read_records(records);
    for (std::size_t p = 0; p < n; ++p) {
        const std::byte* record = records.data() + p * decoder.record_length;
        const Vec3 x = decoder.position(record);
        std::int64_t cell[3];
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
            if (x[a] < g.origin[a] || x[a] > g.origin[a] + g.dims[a] * g.cell_size) {
                inside = false;
                break;
            }
            std::int64_t i = 0;
            while (i + 1 < g.dims[a] && x[a] >= g.origin[a] + (i + 1) * g.cell_size) ++i;
            cell[a] = i;
        }
        if (!inside) {
            ++ref.outside;
            continue;
        }
        const std::uint64_t index = (cell[2] * g.dims[1] + cell[1]) * g.dims[0] + cell[0];
        ++ref.count[index];
        if (decoder.has_color()) {
            const Rgb16 c = decoder.color(record);
            ref.red[index] += c[0], ref.green[index] += c[1], ref.blue[index] += c[2];
        }
    }
    return ref;
}

void check_equal(const DensityGrid& got, const Reference& ref) {
    CHECK(got.points_outside == ref.outside);
    CHECK(got.count == ref.count);
    if (got.has_color()) {
        CHECK(got.red == ref.red);
        CHECK(got.green == ref.green);
        CHECK(got.blue == ref.blue);
    }
}

lasgen::GeneratedPoint at(double x, double y, double z, lasgen::Rgb8 color = {10, 20, 30}) {
    return {{x, y, z}, color, 1};
}

} // namespace

TEST_CASE("points at known positions: cell faces, the upper bound, and outside") {
    test::TempDir dir;
    // Bounds 4 x 2 x 2 with --grid 4: unit cells, 4 x 2 x 2 of them.
    const std::vector<lasgen::GeneratedPoint> points = {
        at(0, 0, 0, {255, 0, 0}),      // the lower corner: cell (0,0,0)
        at(1, 0, 0, {0, 255, 0}),      // on the face between cells 0 and 1: the upper cell
        at(0.99, 1.5, 0.5, {0, 0, 255}),
        at(4, 2, 2, {100, 100, 100}),  // exactly the upper bound: the last cell, not outside
        at(3.5, 1.5, 1.5, {200, 200, 200}),
        at(4.01, 0, 0),                // just above the grid: outside, never clamped
        at(-0.01, 1, 1),               // just below: outside
    };
    test::write_file(dir.file("known.las"), las_with_points(points, {0, 0, 0}, {4, 2, 2}));
    const DensityGrid g = accumulate_file(dir.file("known.las"), grid_of("4"));
    CHECK(g.spec.dims == std::array<std::uint32_t, 3>{4, 2, 2});
    CHECK(g.spec.cell_size == 1.0);
    CHECK(g.points_read == 7);
    CHECK(g.points_outside == 2);
    auto cell = [&](int i, int j, int k) { return std::uint64_t((k * 2 + j) * 4 + i); };
    CHECK(g.count[cell(0, 0, 0)] == 1);
    CHECK(g.count[cell(1, 0, 0)] == 1);
    CHECK(g.count[cell(0, 1, 0)] == 1);
    CHECK(g.count[cell(3, 1, 1)] == 2);
    std::uint64_t total = 0;
    for (std::uint64_t c : g.count) total += c;
    CHECK(total == 5);
    CHECK(!g.color_is_16bit());
    CHECK(g.mean_color(cell(1, 0, 0)) == Rgb8{0, 255, 0});
    CHECK(g.mean_color(cell(3, 1, 1)) == Rgb8{150, 150, 150});
    CHECK(g.red[cell(3, 1, 1)] == 300);
}

TEST_CASE("random clouds: the device grid equals the reference, for every slicing") {
    test::TempDir dir;
    lasgen::SceneOptions scene;
    scene.noise = 0.05;
    scene.origin = {0, 0, 0};
    const lasgen::Scene deck = lasgen::make_scene(scene);
    lasgen::LasLayout layout;
    layout.version_minor = 4;
    layout.point_format = 7;
    layout.color_bits = 16;
    const std::uint64_t n = 20011;
    test::write_file(dir.file("deck.las"), test::make_las(layout, deck, n, 5));

    AccumulateOptions options = grid_of("64");
    const DensityGrid whole = accumulate_file(dir.file("deck.las"), options);
    check_equal(whole, reference_grid(dir.file("deck.las"), whole.spec));
    CHECK(whole.points_read == n);
    CHECK(whole.color_is_16bit());

    const std::size_t record = lasgen::record_length(layout);
    for (std::uint64_t slice : {std::uint64_t{1}, std::uint64_t{7919}}) { // one record; a prime number
        CAPTURE(slice);
        AccumulateOptions sliced = options;
        sliced.slice_bytes = slice * record;
        const DensityGrid g = accumulate_file(dir.file("deck.las"), sliced);
        CHECK(g.count == whole.count);
        CHECK(g.red == whole.red);
        CHECK(g.blue == whole.blue);
    }
    AccumulateOptions small_alloc = options; // a device whose largest allocation is tiny
    small_alloc.max_alloc = whole.spec.cell_count() * 32; // just the grid: slices must shrink to fit
    small_alloc.slice_bytes = 1 << 30;
    const DensityGrid g = accumulate_file(dir.file("deck.las"), small_alloc);
    CHECK(g.count == whole.count);
    CHECK(g.green == whole.green);
}

TEST_CASE("8-bit colour in 16-bit fields and true 16-bit colour give the same mean colours") {
    test::TempDir dir;
    std::vector<lasgen::GeneratedPoint> points;
    for (int i = 0; i < 1000; ++i)
        points.push_back(at((i % 10) + 0.5, (i / 10 % 10) + 0.5, (i / 100) + 0.5,
                            {std::uint8_t(i % 256), std::uint8_t(255 - i % 256), std::uint8_t(i * 7 % 256)}));
    test::write_file(dir.file("c8.las"), las_with_points(points, {0, 0, 0}, {10, 10, 10}, 8));
    test::write_file(dir.file("c16.las"), las_with_points(points, {0, 0, 0}, {10, 10, 10}, 16));
    const DensityGrid g8 = accumulate_file(dir.file("c8.las"), grid_of("10"));
    const DensityGrid g16 = accumulate_file(dir.file("c16.las"), grid_of("10"));
    CHECK(!g8.color_is_16bit());
    CHECK(g16.color_is_16bit());
    for (std::uint64_t c = 0; c < g8.spec.cell_count(); ++c) {
        REQUIRE(g8.count[c] == 1);
        REQUIRE(g8.mean_color(c) == points[c].color); // one point per cell, in cell order
        REQUIRE(g16.mean_color(c) == points[c].color);
    }
}

TEST_CASE("sums beyond 32 bits are exact: 70,000 white 16-bit points in one cell") {
    test::TempDir dir;
    // 70,000 x 65535 = 4,587,450,000 > 2^32: the colour sums must carry into the high word.
    std::vector<lasgen::GeneratedPoint> points(70000, at(0.5, 0.5, 0.5, {255, 255, 255}));
    test::write_file(dir.file("white.las"), las_with_points(points, {0, 0, 0}, {1, 1, 1}, 16));
    const DensityGrid g = accumulate_file(dir.file("white.las"), grid_of("1"));
    REQUIRE(g.count.size() == 1);
    CHECK(g.count[0] == 70000);
    CHECK(g.red[0] == 70000ull * 65535);
    CHECK(g.mean_color(0) == Rgb8{255, 255, 255});
}

TEST_CASE("degenerate extents still give a valid grid") {
    test::TempDir dir;
    SUBCASE("a single point") {
        test::write_file(dir.file("one.las"), las_with_points({at(5, 5, 5)}, {5, 5, 5}, {5, 5, 5}));
        const DensityGrid g = accumulate_file(dir.file("one.las"), grid_of("256"));
        CHECK(g.spec.dims == std::array<std::uint32_t, 3>{1, 1, 1});
        CHECK(g.count[0] == 1);
        CHECK(g.points_outside == 0);
    }
    SUBCASE("a flat cloud") {
        std::vector<lasgen::GeneratedPoint> points;
        for (int i = 0; i <= 10; ++i) points.push_back(at(i, i / 2.0, 3));
        test::write_file(dir.file("flat.las"), las_with_points(points, {0, 0, 3}, {10, 5, 3}));
        const DensityGrid g = accumulate_file(dir.file("flat.las"), grid_of("10"));
        CHECK(g.spec.dims == std::array<std::uint32_t, 3>{10, 5, 1});
        CHECK(g.points_outside == 0);
        check_equal(g, reference_grid(dir.file("flat.las"), g.spec));
    }
    SUBCASE("no points at all") {
        test::write_file(dir.file("none.las"), las_with_points({}, {0, 0, 0}, {0, 0, 0}));
        const DensityGrid g = accumulate_file(dir.file("none.las"), grid_of("8"));
        CHECK(g.points_read == 0);
        CHECK(g.count == std::vector<std::uint64_t>{0});
    }
}

TEST_CASE("--bounds, --voxel and explicit dimensions") {
    test::TempDir dir;
    std::vector<lasgen::GeneratedPoint> points;
    for (int i = 0; i < 100; ++i) points.push_back(at(i * 0.1, 0, 0));
    test::write_file(dir.file("line.las"), las_with_points(points, {0, 0, 0}, {9.9, 0, 0}, 8, 1));
    AccumulateOptions options;
    options.grid = voxel_request(0.5);
    options.bounds = Bounds{{0, -1, -1}, {5, 1, 1}};
    const DensityGrid g = accumulate_file(dir.file("line.las"), options);
    CHECK(g.spec.dims == std::array<std::uint32_t, 3>{10, 4, 4});
    CHECK(!g.has_color());
    CHECK(g.points_outside == 49); // x = 0.0 .. 5.0 are inside (5.0 on the closed top face); 5.1 .. 9.9 are not
    check_equal(g, reference_grid(dir.file("line.las"), g.spec));

    options.grid = parse_grid_request("20x4x4");
    options.bounds.reset();
    const DensityGrid e = accumulate_file(dir.file("line.las"), options);
    CHECK(e.spec.dims == std::array<std::uint32_t, 3>{20, 4, 4});
    CHECK(e.points_outside == 0);
}

TEST_CASE("a grid too large for memory is refused before allocating, with one that fits") {
    test::TempDir dir;
    test::write_file(dir.file("p.las"), las_with_points({at(0, 0, 0), at(10, 10, 10)}, {0, 0, 0}, {10, 10, 10}));
    AccumulateOptions options = grid_of("400");
    options.max_memory = 100ull << 20;
    try {
        accumulate_file(dir.file("p.las"), options);
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::usage);
        const std::string message = e.what();
        CHECK(message.find("400x400x400") != std::string::npos);
        CHECK(message.find("--max-memory") != std::string::npos);
        const std::size_t at = message.find("--grid ");
        REQUIRE(at != std::string::npos);
        // The suggested grid really fits.
        options.grid = parse_grid_request(message.substr(at + 7, message.find(' ', at + 7) - at - 7));
        CHECK(accumulate_file(dir.file("p.las"), options).points_read == 2);
    }
}

TEST_CASE("grid requests and bounds are parsed strictly") {
    CHECK(parse_grid_request("256").dims[0] == 256);
    CHECK(parse_grid_request("512x256x128").dims == std::array<std::uint32_t, 3>{512, 256, 128});
    for (const char* bad : {"", "0", "abc", "12x", "1x2", "1x2x3x4", "-5", "70000"}) {
        CAPTURE(bad);
        CHECK_THROWS_AS(parse_grid_request(bad), Error);
    }
    CHECK(parse_bounds("0,1,2,3,4,5").max == Vec3{3, 4, 5});
    CHECK_THROWS_AS(parse_bounds("0,1,2,3,4"), Error);
    CHECK_THROWS_AS(parse_bounds("0,1,2,3,4,5,6"), Error);
    CHECK_THROWS_AS(parse_bounds("5,0,0,0,1,1"), Error);
    CHECK_THROWS_AS(voxel_request(0), Error);
}

TEST_CASE("a kernel that fails to build reports the compiler's log") {
    try {
        build_program(device().impl(), "broken.cl", "kernel void broken(global int* x) { x[0] = undefined_name; }", "");
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::device);
        const std::string message = e.what();
        CHECK(message.find("kernel broken.cl failed to build") != std::string::npos);
        CHECK(message.find("undefined_name") != std::string::npos); // from the build log
    }
}
