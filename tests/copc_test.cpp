// SPDX-License-Identifier: Apache-2.0
// COPC: the octree's nodes read from a real COPC file (laspy's simple.copc.laz, 65 nodes, in the
// repository), a few chunks decoded alone, damaged hierarchies told, and a plan whose tiles read
// only the nodes that touch them giving the bytes of one run.
#include "lasmesh/build_mesh.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/las_reader.hpp"

#include "byte_order.hpp"
#include "read/copc.hpp"
#include "read/input_stream.hpp"
#include "read/las_header.hpp"

#include <boost/iostreams/filter/gzip.hpp>
#include <doctest/doctest.h>

#include "test_support.hpp"

#include <filesystem>
#include <numeric>

using namespace lasmesh;

namespace {

std::string copc_path() {
    return (std::filesystem::path(LASMESH_SOURCE_DIR) / "tests" / "data" / "laz" / "laspy_simple.copc.laz").string();
}

LasHeader copc_file_header(const std::string& path) {
    InputStream in(path);
    return read_las_header(in);
}

std::vector<std::byte> all_records(LasReader& reader) {
    std::vector<std::byte> records(reader.header().point_count * reader.header().point_record_length);
    CHECK(reader.read_records(records) == reader.header().point_count);
    return records;
}

using test::contains;
using test::error_text;

// The byte where the COPC info VLR's payload starts (its first VLR, as the specification wants).
std::size_t info_payload(const test::Bytes& file) {
    return load_le<std::uint16_t>(file.data() + 94) + 54;
}

} // namespace

TEST_CASE("a COPC file's nodes: in file order, back to back, adding up to the header's count, each point in its "
          "node's cube") {
    const std::string path = copc_path();
    const LasHeader header = copc_file_header(path);
    const auto nodes = read_copc_nodes(path, header);
    REQUIRE(nodes);
    REQUIRE(nodes->size() == 65);                                    // as the hierarchy lists them (checked by hand)
    CHECK(nodes->front().offset == header.offset_to_point_data + 8); // after the chunk table's offset
    std::uint64_t points = 0;
    for (std::size_t i = 0; i < nodes->size(); ++i) {
        points += (*nodes)[i].points;
        if (i > 0) CHECK((*nodes)[i - 1].offset + (*nodes)[i - 1].bytes == (*nodes)[i].offset);
    }
    CHECK(points == 1065);
    // The root: the whole cube, centre 637937.715, 851217.565, 2724.455, half edge 2317.865.
    const auto root = std::find_if(nodes->begin(), nodes->end(), [](const CopcNode& n) { return n.key[0] == 0; });
    REQUIRE(root != nodes->end());
    CHECK(root->cube.min[0] == doctest::Approx(637937.715 - 2317.865));
    CHECK(root->cube.max[2] == doctest::Approx(2724.455 + 2317.865));
    const auto deep = std::find_if(nodes->begin(), nodes->end(), [](const CopcNode& n) {
        return n.key == std::array<std::int32_t, 4>{3, 1, 2, 0};
    });
    REQUIRE(deep != nodes->end());
    const double edge = 2 * 2317.865 / 8;
    CHECK(deep->cube.min[0] == doctest::Approx(637937.715 - 2317.865 + edge));
    CHECK(deep->cube.min[1] == doctest::Approx(851217.565 - 2317.865 + 2 * edge));
    CHECK(deep->cube.max[1] - deep->cube.min[1] == doctest::Approx(edge));

    // Every node's points, decoded from its chunk alone, lie in its cube; and they are the
    // records a whole read gives at that place in the file.
    LasReader whole(path);
    const std::vector<std::byte> every = all_records(whole);
    const std::size_t length = header.point_record_length;
    std::uint64_t first = 0, inside = 0;
    for (const CopcNode& node : *nodes) {
        LasReader part(path);
        part.read_only_chunks({node.offset});
        REQUIRE(part.header().point_count == node.points);
        const std::vector<std::byte> records = all_records(part);
        CHECK(std::equal(records.begin(), records.end(), every.begin() + std::ptrdiff_t(first * length)));
        for (std::size_t i = 0; i < node.points; ++i)
            for (int a = 0; a < 3; ++a) {
                const double v =
                    load_le<std::int32_t>(records.data() + i * length + 4 * a) * header.scale[a] + header.offset[a];
                // Within rounding: a point on the root cube's floor (z 406.59) meets a bound
                // computed as centre - half in doubles.
                const double slack = header.scale[a] / 2;
                inside += v >= node.cube.min[a] - slack && v <= node.cube.max[a] + slack;
            }
        first += node.points;
    }
    CHECK(inside == 3 * 1065);

    // A plain LAZ file has no nodes.
    const std::string plain = (std::filesystem::path(path).parent_path() / "laspy_simple.laz").string();
    CHECK(!read_copc_nodes(plain, copc_file_header(plain)));
}

TEST_CASE("a COPC file read a few chunks at a time: their records in file order, the rest skipped") {
    const std::string path = copc_path();
    const auto nodes = read_copc_nodes(path, copc_file_header(path));
    REQUIRE(nodes);
    LasReader whole(path);
    const std::vector<std::byte> every = all_records(whole);
    const std::size_t length = whole.header().point_record_length;
    std::vector<std::uint64_t> offsets;
    std::vector<std::byte> expected;
    std::uint64_t first = 0;
    for (std::size_t i = 0; i < nodes->size(); ++i) {
        if (i % 3 == 1) {
            offsets.push_back((*nodes)[i].offset);
            expected.insert(expected.end(), every.begin() + std::ptrdiff_t(first * length),
                            every.begin() + std::ptrdiff_t((first + (*nodes)[i].points) * length));
        }
        first += (*nodes)[i].points;
    }
    LasReader part(path);
    part.read_only_chunks(offsets);
    CHECK(part.header().point_count * length == expected.size());
    CHECK(all_records(part) == expected);

    LasReader wrong(path);
    CHECK(contains(error_text([&] { wrong.read_only_chunks({(*nodes)[0].offset + 1}); }),
                   "no LAZ chunk starts at byte " + std::to_string((*nodes)[0].offset + 1)));
    LasReader started(path);
    std::vector<std::byte> one(length);
    started.read_records(one);
    CHECK(contains(error_text([&] { started.read_only_chunks(offsets); }), "read from its start"));
    test::TempDir dir;
    test::write_file(dir.file("p.las"), test::las_with_points({{{1, 2, 3}, {0, 0, 0}, 1}}, {0, 0, 0}, {4, 4, 4}));
    LasReader plain_las(dir.file("p.las"));
    CHECK(contains(error_text([&] { plain_las.read_only_chunks(offsets); }), "only LAZ"));
}

TEST_CASE("a damaged COPC hierarchy: a clear error naming the file and what is wrong") {
    const test::Bytes good = test::read_file(copc_path());
    const std::size_t info = info_payload(good);
    const std::uint64_t root = load_le<std::uint64_t>(good.data() + info + 40);
    test::TempDir dir;
    const std::string path = dir.file("damaged.copc.laz");
    const auto damage = [&](const std::function<void(test::Bytes&)>& change) {
        test::Bytes bytes = good;
        change(bytes);
        test::write_file(path, bytes);
        return error_text([&] { read_copc_nodes(path, copc_file_header(path)); });
    };
    // A node that claims one point more than its chunk holds.
    std::string e = damage([&](test::Bytes& b) {
        store_le<std::int32_t>(b.data() + root + 28, load_le<std::int32_t>(b.data() + root + 28) + 1);
    });
    CHECK(contains(e, path));
    CHECK(contains(e, "nodes hold 1066 points, but the header counts 1065"));
    // The root page past the file's end.
    e = damage([&](test::Bytes& b) { store_le<std::uint64_t>(b.data() + info + 40, good.size() + 64); });
    CHECK(contains(e, "COPC hierarchy page at byte " + std::to_string(good.size() + 64)));
    CHECK(contains(e, "within the file's"));
    // A page that points back at itself.
    e = damage([&](test::Bytes& b) {
        store_le<std::uint64_t>(b.data() + root + 16, root);
        store_le<std::int32_t>(b.data() + root + 24, load_le<std::int32_t>(good.data() + info + 48));
        store_le<std::int32_t>(b.data() + root + 28, -1);
    });
    CHECK(contains(e, "point in a loop"));
    // Two nodes on the same bytes.
    e = damage([&](test::Bytes& b) {
        store_le<std::uint64_t>(b.data() + root + 32 + 16, load_le<std::uint64_t>(b.data() + root + 16));
    });
    CHECK(contains(e, "overlap"));
    // A chunk outside the point data.
    e = damage([&](test::Bytes& b) { store_le<std::uint64_t>(b.data() + root + 16, 100); });
    CHECK(contains(e, "outside the point data"));
}

TEST_CASE("a plan of a COPC file: each tile reads only the nodes that touch it, and merged = one run, byte for "
          "byte") {
    test::TempDir dir;
    const std::string input = dir.file("simple.copc.laz");
    std::filesystem::copy_file(copc_path(), input);
    BuildOptions options;
    options.grid = GridRequest::longest(48);
    OutputRequest one;
    one.path = dir.file("one.ply");
    options.outputs.push_back(one);
    build_mesh(input, options);

    TilePlan plan = plan_tiles({input}, options, 0);
    plan = plan_tiles({input}, options, plan.grid.cell_size * 12); // 12 x 12 cells a tile
    REQUIRE(plan.tiles.size() >= 4);
    write_plan(plan, dir.file("copc.plan.json"));
    const TilePlan read = read_plan(dir.file("copc.plan.json"));
    std::uint64_t in_tiles = 0, read_points = 0, fewest = 1065;
    for (std::size_t k = 0; k < read.tiles.size(); ++k) {
        REQUIRE(read.tiles[k].chunks.size() == 1);
        const PlannedChunks& c = read.tiles[k].chunks.front();
        CHECK(c.offsets.size() < 65);
        const TileReport report = run_tile(read, k, options);
        CHECK(report.points_read == std::accumulate(c.points.begin(), c.points.end(), std::uint64_t{0}));
        in_tiles += report.points_in_tile, read_points += report.points_read;
        fewest = std::min(fewest, report.points_read);
    }
    CHECK(in_tiles == 1065); // every point in exactly one tile
    CHECK(fewest < 1065 / 2);
    CHECK(read_points < read.tiles.size() * 1065 / 2);
    BuildOptions merged = options;
    merged.outputs[0].path = dir.file("merged.ply");
    CHECK(merge_tiles(read, merged).report.points_read == 1065);
    CHECK(test::read_file(dir.file("merged.ply")) == test::read_file(dir.file("one.ply")));
}

TEST_CASE("skipping ahead in an input: a plain file seeks, a compressed stream reads through; the same bytes "
          "follow") {
    test::Bytes bytes(400000);
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = std::byte(i * 7919 % 251);
    test::TempDir dir;
    test::write_file(dir.file("plain"), bytes);
    test::write_file(dir.file("packed.gz"), test::compress(bytes, boost::iostreams::gzip_compressor()));
    for (const std::string name : {"plain", "packed.gz"}) {
        CAPTURE(name);
        InputStream in(dir.file(name));
        std::vector<std::byte> got(10);
        CHECK(in.read(got.data(), 10) == 10);
        CHECK(in.skip(200000) == 200000); // past the 64 KiB below which a plain file reads through too
        CHECK(in.position() == 200010);
        CHECK(in.read(got.data(), 10) == 10);
        CHECK(std::equal(got.begin(), got.end(), bytes.begin() + 200010));
        CHECK(in.skip(100) == 100);
        CHECK(in.read(got.data(), 10) == 10);
        CHECK(std::equal(got.begin(), got.end(), bytes.begin() + 200120));
        CHECK(in.skip(1000000) == 400000 - 200130); // stops at the end
        CHECK(in.read(got.data(), 10) == 0);
    }
}
