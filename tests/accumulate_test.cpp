// SPDX-License-Identifier: Apache-2.0
// Accumulation on the OpenCL device (PoCL in CI) against hand-worked cases and a plain reference
// written here, for every slicing, colour depth and grid edge case.
#include "byte_order.hpp"
#include "cli/option_parsing.hpp" // the option text parsers, from the command line
#include "grid/auto_grid.hpp"
#include "grid/cell_sums.hpp"
#include "grid/compiler_pages.hpp"
#include "grid/opencl_device.hpp" // internal: build_program
#include "lasmesh/error.hpp"
#include "read/las_point.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>

using namespace lasmesh;
using namespace lasmesh::cli;
using test::Bytes;

namespace {

using test::dense;

// The same occupied bricks and cells, each with the same exact sums, positions included (the
// records themselves may lie in `cells` in another order: the device's).
bool sums_equal(const CellGrid& a, const CellGrid& b) {
    if (a.brick_keys != b.brick_keys || a.brick_masks.size() != b.brick_masks.size() ||
        a.cells.size() != b.cells.size())
        return false;
    bool equal = true;
    a.for_each_cell([&](const std::array<std::int64_t, 3>& at, std::uint64_t r) {
        const CellSums* other = b.find(at[0], at[1], at[2]);
        equal = equal && other && a.cells[r].count == other->count && a.cells[r].position == other->position &&
                a.cells[r].color == other->color && a.cells[r].moments == other->moments;
    });
    return equal;
}

using test::accumulate_file;
using test::device;
using test::las_with_points;

AccumulateOptions grid_of(const std::string& text) {
    AccumulateOptions o;
    o.grid = parse_grid_request(text);
    return o;
}

// Exactly this grid: cells of `cell` from `origin`, `dims` of them.
AccumulateOptions exact_grid(Vec3 origin, double cell, std::array<std::uint32_t, 3> dims) {
    AccumulateOptions o;
    o.spec = GridSpec{origin, cell, dims};
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

void check_equal(const CellGrid& sparse, const Reference& ref) {
    const test::DenseGrid got = test::dense(sparse);
    CHECK(sparse.points_outside == ref.outside);
    CHECK(got.count == ref.count);
    if (sparse.has_color()) {
        CHECK(got.red == ref.red);
        CHECK(got.green == ref.green);
        CHECK(got.blue == ref.blue);
    }
}

// `points` points of a lasgen scene at the origin, in point format 3, written to `path`.
void write_scene(const std::string& path, lasgen::SceneKind kind, std::uint64_t points, std::uint64_t seed) {
    lasgen::SceneOptions scene;
    scene.kind = kind;
    scene.origin = {0, 0, 0};
    test::write_file(path, test::make_las(lasgen::LasLayout{}, lasgen::make_scene(scene), points, seed));
}

lasgen::GeneratedPoint at(double x, double y, double z, lasgen::Rgb8 color = {10, 20, 30}) {
    return {{x, y, z}, color, 1};
}

} // namespace

TEST_CASE("points at known positions: cell faces, the upper bound, and outside") {
    test::TempDir dir;
    // Unit cells from the origin, 4 x 2 x 2 of them.
    const std::vector<lasgen::GeneratedPoint> points = {
        at(0, 0, 0, {255, 0, 0}), // the lower corner: cell (0,0,0)
        at(1, 0, 0, {0, 255, 0}), // on the face between cells 0 and 1: the upper cell
        at(0.99, 1.5, 0.5, {0, 0, 255}),
        at(4, 2, 2, {100, 100, 100}), // exactly the upper bound: the last cell, not outside
        at(3.5, 1.5, 1.5, {200, 200, 200}),
        at(4.01, 0, 0),  // just above the grid: outside, never clamped
        at(-0.01, 1, 1), // just below: outside
    };
    test::write_file(dir.file("known.las"), las_with_points(points, {0, 0, 0}, {4, 2, 2}));
    const CellGrid sparse = accumulate_file(dir.file("known.las"), exact_grid({0, 0, 0}, 1, {4, 2, 2}));
    const test::DenseGrid g = test::dense(sparse);
    CHECK(sparse.spec.dims == std::array<std::uint32_t, 3>{4, 2, 2});
    CHECK(sparse.spec.cell_size == 1.0);
    CHECK(sparse.points_read == 7);
    CHECK(sparse.points_outside == 2);
    auto cell = [&](int i, int j, int k) { return std::uint64_t((k * 2 + j) * 4 + i); };
    CHECK(g.count[cell(0, 0, 0)] == 1);
    CHECK(g.count[cell(1, 0, 0)] == 1);
    CHECK(g.count[cell(0, 1, 0)] == 1);
    CHECK(g.count[cell(3, 1, 1)] == 2);
    std::uint64_t total = 0;
    for (std::uint64_t c : g.count) total += c;
    CHECK(total == 5);
    CHECK(!sparse.color_is_16bit());
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
    const CellGrid whole = accumulate_file(dir.file("deck.las"), options);
    check_equal(whole, reference_grid(dir.file("deck.las"), whole.spec));
    CHECK(whole.points_read == n);
    CHECK(whole.color_is_16bit());

    const std::size_t record = lasgen::record_length(layout);
    for (std::uint64_t slice : {std::uint64_t{1}, std::uint64_t{7919}}) { // one record; a prime number
        CAPTURE(slice);
        AccumulateOptions sliced = options;
        sliced.slice_bytes = slice * record;
        const CellGrid g = accumulate_file(dir.file("deck.las"), sliced);
        CHECK(g.brick_keys == whole.brick_keys); // the same layout, whatever order bricks were met in
        CHECK(dense(g).count == dense(whole).count);
        CHECK(dense(g).red == dense(whole).red);
        CHECK(dense(g).blue == dense(whole).blue);
        CHECK(sums_equal(g, whole));
    }
    AccumulateOptions small_alloc = options; // a device whose largest allocation is tiny
    small_alloc.max_alloc =
        whole.brick_keys.size() * brick_device_bytes(true) + 4096; // just the pool: slices must shrink
    small_alloc.slice_bytes = 1 << 30;
    const CellGrid g = accumulate_file(dir.file("deck.las"), small_alloc);
    CHECK(dense(g).count == dense(whole).count);
    CHECK(dense(g).green == dense(whole).green);
    CHECK(sums_equal(g, whole));

    // A pool spread over many small buffers (chunks of 1/8 to 1/4 of it: 5 to 8 of them) holds
    // the same sums.
    AccumulateOptions chunked = options;
    chunked.max_alloc = std::bit_ceil(whole.brick_keys.size() / 8) * brick_device_bytes(true);
    chunked.slice_bytes = 4096 * record;
    REQUIRE(whole.brick_keys.size() >= 64);
    const CellGrid c = accumulate_file(dir.file("deck.las"), chunked);
    CHECK(c.brick_keys == whole.brick_keys);
    CHECK(sums_equal(c, whole));
}

TEST_CASE("a GPU's path (buffers in device memory, filled by the device) gives the same grid") {
    // No GPU is at hand in CI: PoCL's CPU device is used as a discrete GPU is, so the code that
    // clears the index and each new brick, uploads slices and reads the pool back runs anyway.
    test::TempDir dir;
    lasgen::SceneOptions scene;
    scene.noise = 0.05;
    scene.origin = {0, 0, 0};
    lasgen::LasLayout layout;
    layout.point_format = 3;
    const std::uint64_t n = 30011;
    test::write_file(dir.file("deck.las"), test::make_las(layout, lasgen::make_scene(scene), n, 9));
    AccumulateOptions options = grid_of("64");
    const CellGrid host = accumulate_file(dir.file("deck.las"), options);
    options.device_memory = true;
    const CellGrid device = accumulate_file(dir.file("deck.las"), options);
    CHECK(device.points_read == n);
    CHECK(device.brick_keys == host.brick_keys);
    CHECK(device.color_max_word == host.color_max_word);
    CHECK(sums_equal(device, host));
    check_equal(device, reference_grid(dir.file("deck.las"), device.spec));

    // Many small slices (new bricks met in most of them) and a pool in 5 to 8 chunks: each new
    // brick is cleared in whichever chunk holds it.
    REQUIRE(host.brick_keys.size() >= 64);
    options.slice_bytes = 1009 * lasgen::record_length(layout);
    options.max_alloc = std::bit_ceil(host.brick_keys.size() / 8) * brick_device_bytes(true);
    const CellGrid chunked = accumulate_file(dir.file("deck.las"), options);
    CHECK(chunked.brick_keys == host.brick_keys);
    CHECK(sums_equal(chunked, host));
}

TEST_CASE("8-bit colour in 16-bit fields and true 16-bit colour give the same mean colours") {
    test::TempDir dir;
    std::vector<lasgen::GeneratedPoint> points;
    for (int i = 0; i < 1000; ++i)
        points.push_back(at((i % 10) + 0.5, (i / 10 % 10) + 0.5, (i / 100) + 0.5,
                            {std::uint8_t(i % 256), std::uint8_t(255 - i % 256), std::uint8_t(i * 7 % 256)}));
    test::write_file(dir.file("c8.las"), las_with_points(points, {0, 0, 0}, {10, 10, 10}, 8));
    test::write_file(dir.file("c16.las"), las_with_points(points, {0, 0, 0}, {10, 10, 10}, 16));
    const CellGrid s8 = accumulate_file(dir.file("c8.las"), grid_of("10"));
    const CellGrid s16 = accumulate_file(dir.file("c16.las"), grid_of("10"));
    CHECK(!s8.color_is_16bit());
    CHECK(s16.color_is_16bit());
    const test::DenseGrid g8 = test::dense(s8), g16 = test::dense(s16);
    for (std::uint64_t c = 0; c < s8.spec.cell_count(); ++c) {
        REQUIRE(g8.count[c] == 1);
        REQUIRE(g8.mean_color(c) == points[c].color); // one point per cell, in cell order
        REQUIRE(g16.mean_color(c) == points[c].color);
    }
}

TEST_CASE("sums beyond 32 bits are exact: 70,000 white 16-bit points in one cell") {
    test::TempDir dir;
    // 70,000 x 65535 = 4,587,450,000 > 2^32: the colour sums must carry into the high word. The
    // position sums and moments (21-bit lanes) wrap too, though no run of 32 points adds 2^21 to
    // one: each lane's spill into the one above must be taken back from it.
    std::vector<lasgen::GeneratedPoint> points(70000, at(0.4, 0.6, 0.8, {255, 255, 255}));
    test::write_file(dir.file("white.las"), las_with_points(points, {0, 0, 0}, {1, 1, 1}, 16));
    const CellGrid sparse = accumulate_file(dir.file("white.las"), grid_of("1"));
    const test::DenseGrid g = test::dense(sparse); // refers to `sparse` for mean colours
    REQUIRE(g.count.size() == 1);
    CHECK(g.count[0] == 70000);
    CHECK(g.red[0] == 70000ull * 65535);
    CHECK(g.mean_color(0) == Rgb8{255, 255, 255});
    std::array<std::uint64_t, 3> offset{}; // raw units from the cell's start, from the record
    {
        LasReader reader(dir.file("white.las"));
        Bytes record(reader.header().point_record_length);
        REQUIRE(reader.read_records({record.data(), record.size()}) == 1);
        for (int a = 0; a < 3; ++a) {
            std::int32_t raw;
            std::memcpy(&raw, record.data() + 4 * a, 4);
            offset[a] = static_cast<std::uint64_t>(raw - sparse.axes[a].starts[0]);
        }
    }
    const CellSums* cell = sparse.find(0, 0, 0);
    REQUIRE(cell != nullptr);
    REQUIRE(70000 * offset[0] > (std::uint64_t{1} << 21));
    REQUIRE(32 * offset[2] * offset[2] < (std::uint64_t{1} << 21));
    for (int a = 0; a < 3; ++a) CHECK(cell->position[a] == 70000 * offset[a]);
    for (int c = 0; c < 3; ++c) CHECK(cell->color[c] == 70000ull * 65535); // red's wrap spills into green's word
    for (std::size_t k = 0; k < 6; ++k)
        CHECK(cell->moments[k] == 70000 * offset[moment_axes[k][0]] * offset[moment_axes[k][1]]);
}

TEST_CASE("sums beyond their lanes are exact in narrow cells: 20,000 points in a cell 100 raw units wide") {
    // Centimetre scale, 1 m cells: three 21-bit lanes of moments a word. 20,000 points at 99 raw
    // units from the cell's start wrap every position and moment lane many times, each wrap
    // spilling into the lane above, which the carries must take back.
    test::TempDir dir;
    std::vector<lasgen::GeneratedPoint> points(20000, at(0.9901, 0.9901, 0.9901, {255, 255, 255}));
    for (int i = 0; i < 3000; ++i) points.push_back(at(1.5 + (i % 10) * 0.05, 0.5, 0.5)); // a neighbour cell
    test::write_file(dir.file("narrow.las"), las_with_points(points, {0, 0, 0}, {2, 1, 1}, 8, 2, 0.01));
    const CellGrid g = accumulate_file(dir.file("narrow.las"), exact_grid({0, 0, 0}, 1, {2, 1, 1}));
    const CellSums* cell = g.find(0, 0, 0);
    REQUIRE(cell != nullptr);
    CHECK(cell->count == 20000);
    std::array<std::uint64_t, 3> offset{};
    for (int a = 0; a < 3; ++a) offset[a] = static_cast<std::uint64_t>(99 - g.axes[a].starts[0]);
    REQUIRE(offset[0] >= 98);
    for (int a = 0; a < 3; ++a) CHECK(cell->position[a] == 20000 * offset[a]);
    for (std::size_t k = 0; k < 6; ++k)
        CHECK(cell->moments[k] == 20000 * offset[moment_axes[k][0]] * offset[moment_axes[k][1]]);
    for (int c = 0; c < 3; ++c) CHECK(cell->color[c] == 20000u * 255);
    REQUIRE(20000 * offset[0] * offset[0] > (std::uint64_t{1} << 21) * 64); // many times past a 21-bit lane
    const CellSums* next = g.find(1, 0, 0);
    REQUIRE(next != nullptr);
    CHECK(next->count == 3000);
}

TEST_CASE("sums beyond 32 bits are exact: cells a billion raw units wide, whole and in small slices") {
    test::TempDir dir;
    // Scale 1e-8 over 20 m: each of the 2 x 2 x 2 cells is 10^9 raw units wide, so one run of 32
    // points adds more than 2^32 to a position sum, and every sum wraps its low word many times.
    std::vector<lasgen::GeneratedPoint> points;
    std::uint64_t state = 7;
    auto next = [&] { return (state = state * 6364136223846793005ull + 1442695040888963407ull) >> 11; };
    for (int i = 0; i < 60000; ++i) {
        const double spread = i < 40000 ? 10 : 20; // two thirds in cell (0, 0, 0)
        points.push_back(at(double(next() % 1000000) / 1e6 * spread, double(next() % 1000000) / 1e6 * spread,
                            double(next() % 1000000) / 1e6 * spread, {255, 255, 255}));
    }
    test::write_file(dir.file("wide.las"), las_with_points(points, {0, 0, 0}, {20, 20, 20}, 16, 2, 1e-8));
    // The exact sums, from the records as written: raw integers minus the cell's start.
    const CellGrid whole = accumulate_file(dir.file("wide.las"), grid_of("2"));
    std::map<std::array<std::int64_t, 3>, CellSums> expected;
    {
        LasReader reader(dir.file("wide.las"));
        const std::size_t length = reader.header().point_record_length;
        Bytes records(points.size() * length);
        REQUIRE(reader.read_records({records.data(), records.size()}) == points.size());
        for (std::size_t i = 0; i < points.size(); ++i) {
            std::array<std::int64_t, 3> cell{}, raw{};
            for (int a = 0; a < 3; ++a) {
                std::int32_t r;
                std::memcpy(&r, records.data() + i * length + 4 * a, 4);
                raw[a] = r;
                const auto& starts = whole.axes[a].starts;
                cell[a] = std::upper_bound(starts.begin(), starts.end() - 1, raw[a]) - starts.begin() - 1;
            }
            CellSums& sums = expected[cell];
            sums.count += 1;
            std::array<std::uint64_t, 3> offset{};
            for (int a = 0; a < 3; ++a) {
                offset[a] =
                    static_cast<std::uint64_t>(raw[a] - whole.axes[a].starts[static_cast<std::size_t>(cell[a])]);
                sums.position[a] += offset[a];
                sums.color[a] += 65535;
            }
            for (std::size_t k = 0; k < 6; ++k) // modulo 2^64, as the grid keeps them
                sums.moments[k] += offset[moment_axes[k][0]] * offset[moment_axes[k][1]];
        }
    }
    REQUIRE(expected[{0, 0, 0}].position[0] > (std::uint64_t{1} << 44)); // thousands of wraps
    AccumulateOptions sliced = grid_of("2");
    sliced.slice_bytes = 64 << 10; // carries are taken between many slices
    const CellGrid in_slices = accumulate_file(dir.file("wide.las"), sliced);
    for (const CellGrid* g : {&whole, &in_slices}) {
        CHECK(g->occupied_cells() == expected.size());
        for (const auto& [cell, sums] : expected) {
            const CellSums* got = g->find(cell[0], cell[1], cell[2]);
            REQUIRE(got != nullptr);
            CHECK(got->count == sums.count);
            CHECK(got->position == sums.position);
            CHECK(got->color == sums.color);
            CHECK(got->moments == sums.moments);
        }
    }
}

TEST_CASE("degenerate extents still give a valid grid") {
    test::TempDir dir;
    SUBCASE("a single point") {
        test::write_file(dir.file("one.las"), las_with_points({at(5, 5, 5)}, {5, 5, 5}, {5, 5, 5}));
        const CellGrid g = accumulate_file(dir.file("one.las"), grid_of("256"));
        CHECK(g.spec.dims == std::array<std::uint32_t, 3>{1, 1, 1});
        CHECK(dense(g).count[0] == 1);
        CHECK(g.points_outside == 0);
    }
    SUBCASE("a flat cloud") {
        std::vector<lasgen::GeneratedPoint> points;
        for (int i = 0; i <= 10; ++i) points.push_back(at(i, i / 2.0, 3));
        test::write_file(dir.file("flat.las"), las_with_points(points, {0, 0, 3}, {10, 5, 3}));
        const CellGrid g = accumulate_file(dir.file("flat.las"), grid_of("10"));
        // 10 cells of 10 / 9 along x; 5 / (10 / 9) + 1 rounded up along y; z flat, in one cell.
        CHECK(g.spec.dims == std::array<std::uint32_t, 3>{10, 6, 1});
        CHECK(g.spec.origin[2] == doctest::Approx(3 - 5.0 / 9)); // the plane in the middle of its cells
        CHECK(g.points_outside == 0);
        check_equal(g, reference_grid(dir.file("flat.las"), g.spec));
    }
    SUBCASE("no points at all") {
        test::write_file(dir.file("none.las"), las_with_points({}, {0, 0, 0}, {0, 0, 0}));
        const CellGrid g = accumulate_file(dir.file("none.las"), grid_of("8"));
        CHECK(g.points_read == 0);
        CHECK(dense(g).count == std::vector<std::uint64_t>{0});
        CHECK(g.brick_keys.empty());
    }
}

TEST_CASE("grid requests: automatic by default, resolved from the data; cells without a kind are refused") {
    test::TempDir dir;
    std::vector<lasgen::GeneratedPoint> points;
    for (int i = 0; i < 2000; ++i) points.push_back(at((i % 50) * 0.2, (i / 50) * 0.2, 0));
    test::write_file(dir.file("plane.las"), las_with_points(points, {0, 0, 0}, {9.8, 7.8, 0}, 8, 1));
    const CellGrid automatic = accumulate_file(dir.file("plane.las"), AccumulateOptions{});
    CHECK(automatic.grid_reason.rfind("auto: ", 0) == 0);
    AccumulateOptions same;
    same.grid = GridRequest::longest(automatic.spec.dims[0]);
    const CellGrid chosen = accumulate_file(dir.file("plane.las"), same);
    CHECK(chosen.spec.dims == automatic.spec.dims); // the same cells, asked for by number
    CHECK(chosen.grid_reason.empty());
    AccumulateOptions half_set;
    half_set.grid.dims = {64, 0, 0}; // the kind still says automatic
    try {
        accumulate_file(dir.file("plane.las"), half_set);
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::usage);
        CHECK(std::string(e.what()).find("GridRequest::longest(N)") != std::string::npos);
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
    const CellGrid g = accumulate_file(dir.file("line.las"), options);
    // Half a cell to spare each side: 11 x 5 x 5 cells from (-0.25, -1.25, -1.25) to (5.25, 1.25, 1.25).
    CHECK(g.spec.dims == std::array<std::uint32_t, 3>{11, 5, 5});
    CHECK(g.spec.origin[0] == -0.25);
    CHECK(!g.has_color());
    CHECK(g.points_outside == 47); // x = 0.0 .. 5.2 are inside; 5.3 .. 9.9 are not
    check_equal(g, reference_grid(dir.file("line.las"), g.spec));

    options.grid = parse_grid_request("20x4x4");
    options.bounds.reset();
    const CellGrid e = accumulate_file(dir.file("line.las"), options);
    CHECK(e.spec.dims == std::array<std::uint32_t, 3>{20, 4, 4});
    CHECK(e.points_outside == 0);
}

TEST_CASE("a grid too large for memory is refused before allocating, with one that fits") {
    test::TempDir dir;
    test::write_file(dir.file("p.las"), las_with_points({at(0, 0, 0), at(10, 10, 10)}, {0, 0, 0}, {10, 10, 10}));
    // The sparse grid's brick index is the part known before reading: 1600^3 cells need a
    // 256 MB index at 4^3 cells a brick.
    AccumulateOptions options = grid_of("1600");
    options.max_memory = 100ull << 20;
    try {
        accumulate_file(dir.file("p.las"), options);
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::usage);
        const std::string message = e.what();
        CHECK(message.find("1600x1600x1600") != std::string::npos);
        CHECK(message.find("more than the memory limit") != std::string::npos);
        // The suggested grid, in the message and as a value for the option, really fits.
        CHECK(e.option() == "grid");
        REQUIRE(!e.suggestion().empty());
        CHECK(message.find("a grid of " + e.suggestion() + " cells would fit") != std::string::npos);
        options.grid = parse_grid_request(e.suggestion());
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

TEST_CASE("once a program is built, the compiler's clean pages are no longer resident") {
    CHECK(is_compiler_library("/usr/lib/x86_64-linux-gnu/libLLVM-15.so.1"));
    CHECK(is_compiler_library("/usr/lib/llvm-15/lib/libclang-cpp.so.15"));
    CHECK(!is_compiler_library("/usr/lib/x86_64-linux-gnu/libc.so.6"));
    CHECK(!is_compiler_library("/opt/libLLVM/lib/libpocl.so.2")); // by the file's name, not its folder's
    const cl::Program program =
        build_program(device().impl(), "probe.cl", "kernel void probe(global int* x) { x[0] = 1; }", "");
    const std::vector<CompilerMapping> mappings = compiler_mappings(); // while the program is held
    // PoCL, the suite's device, compiles with LLVM and clang: their read-only mappings are found,
    // and none is left resident (a page or two another thread touched since, at most).
    if (device().info().platform.find("Portable Computing Language") != std::string::npos) CHECK(mappings.size() >= 2);
    std::size_t resident = 0;
    for (const CompilerMapping& m : mappings) resident += m.resident;
    CHECK(resident <= 64 * 1024);
}

TEST_CASE("sparse grid: position sums give each cell's centroid exactly") {
    test::TempDir dir;
    // Three points in cell (0,0,0) and one in cell (3,1,1) of unit cells; coordinates in mm.
    const std::vector<lasgen::GeneratedPoint> points = {at(0.1, 0.2, 0.3), at(0.2, 0.4, 0.6), at(0.3, 0.6, 0.9),
                                                        at(3.25, 1.5, 1.75), at(4, 2, 2)};
    test::write_file(dir.file("m.las"), las_with_points(points, {0, 0, 0}, {4, 2, 2}));
    const CellGrid g = accumulate_file(dir.file("m.las"), exact_grid({0, 0, 0}, 1, {4, 2, 2}));
    const CellSums* first = g.find(0, 0, 0);
    REQUIRE(first != nullptr);
    CHECK(first->count == 3);
    const Vec3 c = g.centroid({0, 0, 0}, *first);
    CHECK(c[0] == doctest::Approx(0.2).epsilon(1e-9));
    CHECK(c[1] == doctest::Approx(0.4).epsilon(1e-9));
    CHECK(c[2] == doctest::Approx(0.6).epsilon(1e-9));
    const CellSums* last = g.find(3, 1, 1);
    REQUIRE(last != nullptr);
    CHECK(last->count == 2);
    const Vec3 m = g.centroid({3, 1, 1}, *last);
    CHECK(m[0] == doctest::Approx(3.625));
    CHECK(m[1] == doctest::Approx(1.75));
    CHECK(m[2] == doctest::Approx(1.875));
    CHECK(g.find(1, 0, 0) == nullptr); // same brick as (0,0,0), but no point: not kept
    CHECK(g.count(1, 0, 0) == 0);
    CHECK(g.brick_masks.size() == 1);
    CHECK(g.brick_masks[0] ==
          ((std::uint64_t{1} << 0) | (std::uint64_t{1} << ((1 * 4 + 1) * 4 + 3)))); // cells (0,0,0), (3,1,1)
    CHECK(g.occupied_cells() == 2);
    CHECK(g.find(4, 0, 0) == nullptr); // outside the grid
}

TEST_CASE("sparse grid: memory follows the surface, and a pool that outgrows the limit stops with advice") {
    test::TempDir dir;
    write_scene(dir.file("s.las"), lasgen::SceneKind::sphere, 200000, 3);
    const CellGrid coarse = accumulate_file(dir.file("s.las"), grid_of("64"));
    const CellGrid fine = accumulate_file(dir.file("s.las"), grid_of("256"));
    // A surface: 4 x 4 = 16 times the cells would be 64 times for a volume.
    const double growth = double(fine.brick_keys.size()) / double(coarse.brick_keys.size());
    CHECK(growth > 8);
    CHECK(growth < 24);
    CHECK(fine.points_read == 200000);

    AccumulateOptions options = grid_of("256");
    options.max_memory = 24ull << 20; // the index and slices fit, the pool does not
    options.slice_bytes = 1 << 20;
    try {
        accumulate_file(dir.file("s.las"), options);
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::usage);
        const std::string message = e.what();
        CAPTURE(message);
        CHECK(message.find("bricks") != std::string::npos);
        CHECK(message.find("of 200000 points") != std::string::npos);
        CHECK(e.option() == "grid");
        REQUIRE(!e.suggestion().empty());
        CHECK(message.find("a grid of " + e.suggestion() + " cells would fit") != std::string::npos);
        options.grid = parse_grid_request(e.suggestion());
        CHECK(accumulate_file(dir.file("s.las"), options).points_read == 200000);
    }
}

TEST_CASE("--grid auto's coarsening: merged cells hold exactly what accumulating at twice the cell gives") {
    test::TempDir dir;
    write_scene(dir.file("t.las"), lasgen::SceneKind::torus, 30000, 9);
    // Cells of h = 0.2 and exactly 2h from one origin, every axis even: merged fine cells are
    // the coarse cells.
    const Vec3 origin{-5.1, -5.1, -2.3};
    const CellGrid fine = accumulate_file(dir.file("t.las"), exact_grid(origin, 0.2, {52, 52, 24}));
    const CellGrid direct = accumulate_file(dir.file("t.las"), exact_grid(origin, 0.4, {26, 26, 12}));
    REQUIRE(fine.points_outside == 0);
    const CellGrid merged = coarsen_grid(fine);
    CHECK(merged.spec.dims == direct.spec.dims);
    CHECK(merged.spec.cell_size == direct.spec.cell_size);
    for (int a = 0; a < 3; ++a) CHECK(merged.axes[a].starts == direct.axes[a].starts);
    CHECK(merged.brick_keys == direct.brick_keys);
    CHECK(sums_equal(merged, direct));
    CHECK(merged.points_read == fine.points_read);
    CHECK(merged.median_count() >= fine.median_count());

    // An odd axis: its last coarse cell covers the fine grid's last cell and ends where it ended.
    const CellGrid odd = accumulate_file(dir.file("t.las"), exact_grid(origin, 0.2, {63, 52, 24}));
    const CellGrid odd_merged = coarsen_grid(odd);
    CHECK(odd_merged.spec.dims[0] == 32);
    CHECK(odd_merged.axes[0].starts.back() == odd.axes[0].starts.back());
    std::uint64_t total = 0;
    for (const CellSums& c : odd_merged.cells) total += c.count;
    CHECK(total == odd.points_read - odd.points_outside);
}

// The cells of `g` with x in [x0, x1), as a part of it (its frame, its bricks cut to those cells).
CellGrid cells_in_x(const CellGrid& g, std::int64_t x0, std::int64_t x1) {
    CellGrid part = empty_like(g);
    for (std::size_t b = 0; b < g.brick_keys.size(); ++b) {
        std::uint64_t mask = 0;
        std::vector<CellSums> kept;
        std::uint64_t record = g.brick_first[b];
        for (std::uint64_t m = g.brick_masks[b]; m != 0; m &= m - 1, ++record) {
            const auto bit = static_cast<unsigned>(std::countr_zero(m));
            const std::int64_t x = g.cell_in_brick(g.brick_keys[b], bit)[0];
            if (x < x0 || x >= x1) continue;
            mask |= std::uint64_t{1} << bit;
            kept.push_back(g.cells[record]);
        }
        if (mask != 0) append_brick(part, g.brick_keys[b], mask, kept.data());
    }
    part.index_bricks();
    return part;
}

TEST_CASE("a grid coarsened part by part and the parts summed: the grid coarsened whole") {
    // Parts cut at x = 4 and 24 (as tiles of whole bricks are) and at x = 13 and 31 (odd: a
    // coarse cell then takes its fine cells from two parts, whose sums must be added).
    test::TempDir dir;
    write_scene(dir.file("t.las"), lasgen::SceneKind::torus, 30000, 9);
    const CellGrid fine = accumulate_file(dir.file("t.las"), exact_grid({-5.1, -5.1, -2.3}, 0.2, {52, 52, 24}));
    const CellGrid whole = coarsen_grid(fine);
    for (const std::array<std::int64_t, 2> cuts : {std::array<std::int64_t, 2>{4, 24}, {13, 31}}) {
        CAPTURE(cuts[0]);
        std::vector<CellGrid> parts;
        std::uint64_t cells = 0;
        for (const auto& [x0, x1] :
             {std::pair<std::int64_t, std::int64_t>{0, cuts[0]}, {cuts[0], cuts[1]}, {cuts[1], 52}}) {
            parts.push_back(coarsen_grid(cells_in_x(fine, x0, x1)));
            cells += parts.back().cells.size();
        }
        if (cuts[0] == 13) CHECK(cells > whole.cells.size() + 20); // coarse cells held by two parts
        const CellGrid summed = sum_of_parts(std::move(parts));
        CHECK(summed.spec.dims == whole.spec.dims);
        CHECK(summed.brick_masks == whole.brick_masks);
        CHECK(sums_equal(summed, whole));
    }
}

TEST_CASE("points on the header's bounds are inside the grid, even where the scale rounds them past it") {
    test::TempDir dir;
    // 487881702 x 0.01 is 4878817.0200000005 in doubles: past a header maximum of 4878817.02.
    std::vector<lasgen::GeneratedPoint> points;
    for (int i = 0; i <= 100; ++i)
        points.push_back(at(4878816.02 + i * 0.01, 100 + (i % 10) * 0.1, 10 + (i / 10) * 0.1));
    test::write_file(dir.file("edge.las"),
                     las_with_points(points, {4878816.02, 100, 10}, {4878817.02, 100.9, 11}, 8, 1, 0.01));
    LasReader reader(dir.file("edge.las"));
    REQUIRE(reader.header().max[0] == 4878817.02);
    std::vector<std::byte> records(101 * reader.header().point_record_length);
    REQUIRE(reader.read_records(records) == 101);
    const PointDecoder decoder(reader.header());
    CHECK(decoder.position(records.data() + 100 * decoder.record_length)[0] > 4878817.02); // the rounding
    for (const char* grid : {"8", "64", "1000"}) {
        CAPTURE(grid);
        const CellGrid g = accumulate_file(dir.file("edge.las"), grid_of(grid));
        CHECK(g.points_outside == 0);
        std::uint64_t total = 0;
        for (const CellSums& c : g.cells) total += c.count;
        CHECK(total == 101);
    }
}

namespace {

// Every sum of every cell, worked out here from the raw records in plain loops: a cell's start on
// an axis is the smallest raw integer whose coordinate (raw * scale + offset, in doubles, as LAS
// defines it) reaches origin + i * cell, found by stepping from an estimate, not the library's
// bisection; the last cell is closed at its top.
struct HostSums {
    std::map<std::array<std::int64_t, 3>, CellSums> cells;
    std::uint64_t outside = 0;
};

HostSums host_sums(const std::string& path, const GridSpec& g) {
    LasReader reader(path);
    const LasHeader& h = reader.header();
    std::array<std::vector<std::int64_t>, 3> starts;
    for (int a = 0; a < 3; ++a)
        for (std::uint32_t i = 0; i <= g.dims[a]; ++i) {
            const double limit = g.origin[a] + i * g.cell_size;
            const bool closed = i == g.dims[a]; // the top: the first raw strictly above it
            const auto passes = [&](std::int64_t r) {
                const double x = static_cast<double>(r) * h.scale[a] + h.offset[a];
                return closed ? x > limit : x >= limit;
            };
            auto r = static_cast<std::int64_t>(std::floor((limit - h.offset[a]) / h.scale[a]));
            while (passes(r - 1)) --r;
            while (!passes(r)) ++r;
            starts[a].push_back(r);
        }
    const PointDecoder decoder(h);
    const int rgb = rgb_offset(h.point_format);
    HostSums sums;
    Bytes records(h.point_count * decoder.record_length + 1);
    const std::size_t n = reader.read_records(records);
    for (std::size_t p = 0; p < n; ++p) {
        const std::byte* record = records.data() + p * decoder.record_length;
        std::array<std::int64_t, 3> cell{}, raw{};
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
            raw[a] = load_le<std::int32_t>(record + 4 * a);
            if (raw[a] < starts[a].front() || raw[a] >= starts[a].back())
                inside = false;
            else
                while (raw[a] >= starts[a][static_cast<std::size_t>(cell[a]) + 1]) ++cell[a];
        }
        if (!inside) {
            ++sums.outside;
            continue;
        }
        CellSums& c = sums.cells[cell];
        ++c.count;
        std::array<std::uint64_t, 3> offset{};
        for (int a = 0; a < 3; ++a) {
            offset[a] = static_cast<std::uint64_t>(raw[a] - starts[a][static_cast<std::size_t>(cell[a])]);
            c.position[a] += offset[a];
            if (rgb >= 0) c.color[a] += load_le<std::uint16_t>(record + rgb + 2 * a);
        }
        for (std::size_t k = 0; k < 6; ++k) c.moments[k] += offset[moment_axes[k][0]] * offset[moment_axes[k][1]];
    }
    return sums;
}

void check_against_host(const CellGrid& g, const HostSums& expected) {
    CHECK(g.points_outside == expected.outside);
    CHECK(g.occupied_cells() == expected.cells.size());
    std::size_t wrong = 0;
    for (const auto& [cell, sums] : expected.cells) {
        const CellSums* got = g.find(cell[0], cell[1], cell[2]);
        const bool same = got && got->count == sums.count && got->position == sums.position &&
                          (!g.has_color() || got->color == sums.color) && got->moments == sums.moments;
        if (!same && ++wrong <= 3) {
            MESSAGE("cell " << cell[0] << " " << cell[1] << " " << cell[2] << ": expected count " << sums.count
                            << ", position " << sums.position[0] << " " << sums.position[1] << " " << sums.position[2]);
            if (got)
                MESSAGE("got count " << got->count << ", position " << got->position[0] << " " << got->position[1]
                                     << " " << got->position[2]);
        }
    }
    CHECK(wrong == 0);
}

} // namespace

TEST_CASE("every cell's count, position and colour sums equal a plain host accumulation of the same records") {
    test::TempDir dir;
    SUBCASE("runs of records on a cell's start along y, off it along x and z (the sums a flush can skip)") {
        // In acquisition order, 40 records a cell: a run's y offsets add up to 0, its z offsets do not.
        std::vector<lasgen::GeneratedPoint> points;
        std::uint64_t state = 5;
        auto next = [&] {
            return double((state = state * 6364136223846793005ull + 1442695040888963407ull) >> 11) / double(1ull << 53);
        };
        for (int cell = 0; cell < 300; ++cell)
            for (int k = 0; k < 40; ++k)
                points.push_back(at((cell % 10) + 0.01 + 0.98 * next(), (cell / 10 % 6),
                                    (cell / 60) + 0.01 + 0.98 * next(), {std::uint8_t(cell), std::uint8_t(k), 7}));
        test::write_file(dir.file("runs.las"), las_with_points(points, {0, 0, 0}, {10, 6, 5}, 16, 3, 0.001));
        const AccumulateOptions options = exact_grid({0, 0, 0}, 1, {10, 6, 5});
        const HostSums expected = host_sums(dir.file("runs.las"), *options.spec);
        REQUIRE(expected.cells.size() == 300);
        REQUIRE(expected.cells.begin()->second.position[1] == 0);
        REQUIRE(expected.cells.begin()->second.position[2] > 0);
        check_against_host(accumulate_file(dir.file("runs.las"), options), expected);
    }
    SUBCASE(
        "a scene far from the origin (negative and large offsets), in slices of 7 and 4,096 records, bricks crossed") {
        lasgen::SceneOptions scene;
        scene.origin = {-431250.25, 6700200.5, -12.75};
        scene.noise = 0.03;
        lasgen::LasLayout layout;
        layout.offset = {-431000, 6700000, -100};
        layout.scale = {0.0005, 0.0005, 0.00025};
        test::write_file(dir.file("far.las"), test::make_las(layout, lasgen::make_scene(scene), 30011, 17));
        for (const char* grid : {"37", "200"}) {
            CAPTURE(grid);
            AccumulateOptions options = grid_of(grid);
            const CellGrid whole = accumulate_file(dir.file("far.las"), options);
            const HostSums expected = host_sums(dir.file("far.las"), whole.spec);
            check_against_host(whole, expected);
            for (const std::uint64_t records : {7u, 4096u}) {
                CAPTURE(records);
                options.slice_bytes = records * lasgen::record_length(layout);
                check_against_host(accumulate_file(dir.file("far.las"), options), expected);
            }
        }
    }
}

TEST_CASE("--grid auto's second look: coarsened until the occupied cells' median count reaches 4, and no further") {
    test::TempDir dir;
    write_scene(dir.file("s.las"), lasgen::SceneKind::sphere, 20000, 4);
    CellGrid grid = accumulate_file(dir.file("s.las"), grid_of("512")); // far too fine: about a point a cell
    const std::uint64_t min_median = auto_grid_min_median(auto_grid_most_points_per_cell);
    REQUIRE(min_median == 4);
    REQUIRE(grid.median_count() < min_median);
    // The same merges by hand: while the median is under 4.
    CellGrid by_hand = accumulate_file(dir.file("s.las"), grid_of("512"));
    int merges = 0;
    while (by_hand.median_count() < min_median) by_hand = coarsen_grid(by_hand), ++merges;
    REQUIRE(merges >= 2);
    const std::string said = coarsen_while_sparse(grid, min_median);
    CHECK(grid.spec.dims == by_hand.spec.dims);
    CHECK(grid.median_count() >= min_median);
    CHECK(said.find(std::to_string(1 << merges) + " times coarser") != std::string::npos);
    CHECK(coarsen_while_sparse(grid, min_median).empty()); // dense enough: left alone
}

TEST_CASE("a grid too fine for its points: coarsened while most occupied cells hold a single point") {
    test::TempDir dir;
    write_scene(dir.file("s.las"), lasgen::SceneKind::sphere, 20000, 4);
    CellGrid grid = accumulate_file(dir.file("s.las"), grid_of("1024"));
    REQUIRE(grid.median_count() == 1);
    CellGrid by_hand = accumulate_file(dir.file("s.las"), grid_of("1024"));
    int merges = 0;
    while (by_hand.median_count() == 1) by_hand = coarsen_grid(by_hand), ++merges;
    REQUIRE(merges >= 1);
    CHECK(coarsen_while_single_points(grid) == merges);
    CHECK(grid.spec.dims == by_hand.spec.dims);
    CHECK(grid.median_count() > 1);
    CHECK(grid.occupied_cells() == by_hand.occupied_cells());
    CHECK(grid.points_read == by_hand.points_read);
    CHECK(coarsen_while_single_points(grid) == 0); // two points a cell or more: left alone
    CHECK(grid.median_count() < auto_grid_min_median(auto_grid_most_points_per_cell)); // finer than 12 a cell leaves it
}
