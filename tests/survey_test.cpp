// SPDX-License-Identifier: Apache-2.0
// A survey of several files meshed as one cloud: the same mesh as one file holding all the points,
// whatever the order of the files, their offsets, scales and point formats; bad files stop the run
// or, when asked, are left out exactly; coordinate systems must agree.
#include "byte_order.hpp"
#include "grid/cell_sums.hpp"
#include "lasmesh/build_mesh.hpp"
#include "lasmesh/compare.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/mesh_files.hpp"
#include "measure/mesh_distance.hpp"
#include "read/crs_transform.hpp"
#include "read/survey.hpp"

#include <boost/iostreams/filter/gzip.hpp>
#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>

using namespace lasmesh;

namespace {

constexpr std::uint64_t points = 60000;

using test::contains;

// A deck scene (at UTM-like coordinates, where offsets matter) and its files.
struct Split {
    test::TempDir dir;
    lasgen::Scene scene = [] {
        lasgen::SceneOptions options;
        options.origin = {431250, 6700200, 10};
        return lasgen::make_scene(options);
    }();
    lasgen::LasLayout layout() const {
        lasgen::LasLayout l;
        for (int a = 0; a < 3; ++a) l.offset[a] = std::floor(scene.min[a]);
        return l;
    }
    std::string whole() const {
        const std::string path = dir.file("whole.las");
        test::write_file(path, test::make_las_part(layout(), scene, 0, points));
        return path;
    }
    // The points in `parts` files, file k in layouts[k % layouts.size()].
    std::vector<std::string> split(const std::string& name, std::size_t parts,
                                   const std::vector<lasgen::LasLayout>& layouts) const {
        std::vector<std::string> paths;
        for (std::size_t k = 0; k < parts; ++k) {
            paths.push_back(dir.file(name + std::to_string(k) + ".las"));
            const std::uint64_t first = points * k / parts, end = points * (k + 1) / parts;
            test::write_file(paths.back(), test::make_las_part(layouts[k % layouts.size()], scene, first, end - first));
        }
        return paths;
    }
    BuildOptions options(const std::string& output) const {
        BuildOptions o;
        o.grid = GridRequest::longest(96);
        OutputRequest request;
        request.path = dir.file(output);
        o.outputs.push_back(request);
        o.keep_mesh = true;
        return o;
    }
};

Error error_of(const std::vector<std::string>& inputs, const BuildOptions& options) {
    try {
        build_mesh(inputs, options);
    } catch (const Error& e) {
        return e;
    }
    FAIL("no error");
    return Error(ErrorKind::usage, "");
}

// The mean distance from the vertices of `a` to the surface of `b`, in world units.
double mean_distance(const Mesh& a, const Mesh& b) {
    const TriangleSearch search(b);
    double sum = 0;
    for (const auto& p : a.positions) {
        const Vec3 world{p[0] + a.origin[0] - b.origin[0], p[1] + a.origin[1] - b.origin[1],
                         p[2] + a.origin[2] - b.origin[2]};
        sum += search.distance(world);
    }
    return a.positions.empty() ? INFINITY : sum / static_cast<double>(a.positions.size());
}

} // namespace

TEST_CASE("survey: files in one frame mesh to the single file's bytes, in any order") {
    Split s;
    const std::string whole = s.whole();
    std::vector<std::string> parts = s.split("part", 5, {s.layout()});
    build_mesh(whole, s.options("whole.ply"));
    const BuildResult result = build_mesh(parts, s.options("parts.ply"));
    CHECK(result.report.input == "5 files");
    CHECK(result.report.input_files == 5);
    CHECK(result.report.points_read == points);
    CHECK(test::read_file(s.dir.file("parts.ply")) == test::read_file(s.dir.file("whole.ply")));
    std::reverse(parts.begin(), parts.end());
    std::rotate(parts.begin(), parts.begin() + 2, parts.end());
    build_mesh(parts, s.options("shuffled.ply"));
    CHECK(test::read_file(s.dir.file("shuffled.ply")) == test::read_file(s.dir.file("whole.ply")));
}

TEST_CASE("survey: small compressed files are decoded several at once and handed out in order") {
    Split s;
    const std::vector<std::string> plain = s.split("part", 13, {s.layout()});
    std::vector<std::string> packed; // gzip streams, and a file without points among them
    for (std::size_t k = 0; k < plain.size(); ++k) {
        packed.push_back(plain[k] + ".gz");
        test::write_file(packed.back(), test::compress(test::read_file(plain[k]), boost::iostreams::gzip_compressor()));
        if (k == 4) {
            packed.push_back(s.dir.file("empty.las.gz"));
            test::write_file(packed.back(), test::compress(test::make_las_part(s.layout(), s.scene, 0, 0),
                                                           boost::iostreams::gzip_compressor()));
        }
    }
    // Every record in the plain files' order, read in slices that end inside files.
    const auto all_records = [](const std::vector<std::string>& paths, std::size_t slice,
                                std::optional<std::size_t>* failed = nullptr) {
        const lasmesh::Survey survey = read_survey(paths, SurveyOptions{});
        SurveyReader reader(survey);
        test::Bytes all, buffer(slice * survey.header.point_record_length);
        try {
            while (std::size_t n = reader.read_records(buffer))
                all.insert(all.end(), buffer.begin(), buffer.begin() + n * survey.header.point_record_length);
        } catch (const Error&) {
            if (!failed) throw;
            *failed = reader.failed_file();
        }
        return all;
    };
    tbb::task_arena two(2); // batches of two files, whatever this machine's cores
    two.execute([&] {
        const test::Bytes expected = all_records(plain, 100000);
        CHECK(expected.size() == points * 34);
        CHECK(all_records(packed, 777) == expected);
        CHECK(all_records(packed, 100000) == expected);

        // The 8th stream (7th part) cut short: named when its turn comes, after the records of
        // the files before it and none of its own (read a record at a time: a read that throws
        // hands out nothing).
        test::Bytes cut = test::read_file(packed[7]);
        cut.resize(cut.size() / 2);
        test::write_file(packed[7], cut);
        std::optional<std::size_t> failed;
        const test::Bytes before = all_records(packed, 1, &failed);
        CHECK(failed == std::optional<std::size_t>(7));
        CHECK(before.size() == points * 6 / 13 * 34);
        CHECK(std::equal(before.begin(), before.end(), expected.begin()));
        const Error e = error_of(packed, s.options("cut.ply"));
        CHECK(contains(e.what(), "part6.las.gz"));
    });
}

TEST_CASE("survey: files with their own offsets, scales and formats: one frame, the same sums, any order") {
    Split s;
    const std::string whole = s.whole();
    std::vector<lasgen::LasLayout> layouts(3, s.layout());
    layouts[1].offset = {431000, 6700000, 0}; // whole metres apart: brought over exactly
    layouts[1].point_format = 2;              // another record layout
    layouts[2].point_format = 7, layouts[2].version_minor = 4;
    layouts[2].offset = {431250.37, 6700200.11, 10.5}; // still whole steps of the scale apart
    std::vector<std::string> parts = s.split("part", 6, layouts);

    // The same points in another frame and layout: every cell's count and sums the same.
    AccumulateOptions accumulate;
    accumulate.grid = GridRequest::longest(96);
    LasReader one_reader(whole);
    const CellGrid one_grid = accumulate_cells(one_reader, test::device(), accumulate);
    const lasmesh::Survey survey = read_survey(parts, SurveyOptions{});
    CHECK(survey.header.offset == std::array<double, 3>{431000, 6700000, 0});
    CHECK(survey.header.point_format == 2);
    SurveyReader parts_reader(survey);
    const CellGrid parts_grid = accumulate_cells(parts_reader, test::device(), accumulate);
    REQUIRE(parts_grid.spec.dims == one_grid.spec.dims);
    std::uint64_t cells = 0, same = 0;
    one_grid.for_each_cell([&](const std::array<std::int64_t, 3>& at, std::uint64_t record) {
        const CellSums& a = one_grid.cells[record];
        const CellSums* b = parts_grid.find(at[0], at[1], at[2]);
        ++cells;
        same += b && b->count == a.count && b->position == a.position && b->color == a.color && b->moments == a.moments;
    });
    CHECK(cells == parts_grid.occupied_cells());
    CHECK(same == cells);

    // The mesh: the centroids differ by rounding (1e-10 of a cell), which the sheet's ties
    // turn into a few other triangles: within a hundredth of a cell on average.
    BuildOptions o = s.options("whole.ply");
    o.simplify.error = 0; // the extracted surfaces themselves
    const BuildResult one = build_mesh(whole, o);
    const double cell = one.report.grid.cell_size;
    o.outputs[0].path = s.dir.file("parts.ply");
    const BuildResult all = build_mesh(parts, o);
    REQUIRE(all.mesh);
    CHECK(all.report.points_read == points);
    CHECK(all.report.colored);
    CHECK(mean_distance(*all.mesh, *one.mesh) <= 0.01 * cell);
    CHECK(mean_distance(*one.mesh, *all.mesh) <= 0.01 * cell);
    std::reverse(parts.begin(), parts.end());
    o.outputs[0].path = s.dir.file("reversed.ply");
    build_mesh(parts, o);
    CHECK(test::read_file(s.dir.file("reversed.ply")) == test::read_file(s.dir.file("parts.ply")));

    // Files at half the scale hold other points (rounded to 0.5 mm, not 1 mm): the frame takes
    // the finer scale, and the surface moves as little as those points do, cells near the iso
    // flipping: within 2% of a cell (a file brought over a step off would be a cell off).
    layouts[0].scale = {0.0005, 0.0005, 0.0005};
    o.outputs[0].path = s.dir.file("finer.ply");
    const BuildResult finer = build_mesh(s.split("finer", 6, layouts), o);
    REQUIRE(finer.mesh);
    CHECK(mean_distance(*finer.mesh, *one.mesh) <= 0.02 * cell);
    CHECK(mean_distance(*one.mesh, *finer.mesh) <= 0.02 * cell);
}

TEST_CASE("survey: each record lands where its file put it: exactly, or on the frame's nearest step") {
    Split s;
    std::vector<lasgen::LasLayout> layouts(4, s.layout());
    layouts[1].offset = {431000, 6700000, 0};
    layouts[1].point_format = 1;    // no colour: the survey's records get colour 0
    layouts[2].offset[0] += 0.0004; // between the frame's steps: rounded to the nearest
    layouts[3].scale = {0.0005, 0.0005, 0.0005};
    const std::vector<std::string> parts = s.split("part", 4, layouts);
    const lasmesh::Survey survey = read_survey(parts, SurveyOptions{});
    REQUIRE(survey.header.point_format == 2);
    const double step = survey.header.scale[0];
    CHECK(step == 0.0005);
    SurveyReader records(survey);
    const std::size_t length = survey.header.point_record_length;
    std::vector<std::byte> buffer(4096 * length);
    std::vector<LasPoint> expected(4096);
    for (std::size_t k = 0; k < parts.size(); ++k) {
        LasReader file(parts[k]);
        double worst = 0;
        bool colour_kept = true;
        while (const std::size_t n = read_points(file, expected)) {
            REQUIRE(records.read_records({buffer.data(), n * length}) == n);
            for (std::size_t i = 0; i < n; ++i) {
                const std::byte* record = buffer.data() + i * length;
                for (int a = 0; a < 3; ++a) {
                    std::int32_t raw = 0;
                    std::memcpy(&raw, record + 4 * a, 4); // little-endian hosts only run these tests
                    const double at = raw * survey.header.scale[a] + survey.header.offset[a];
                    worst = std::max(worst, std::abs(at - expected[i].position[a]));
                }
                std::array<std::uint16_t, 3> color{};
                std::memcpy(color.data(), record + 20, 6);
                colour_kept = colour_kept && color == expected[i].color;
            }
        }
        CAPTURE(k);
        // part2's points lie 0.4 mm off the frame's 0.5 mm steps: 0.1 mm from the nearest, where
        // they land (rounding down would move them 0.4 mm).
        CHECK(worst <= (k == 2 ? 0.0001 + 1e-9 : 1e-9));
        CHECK(worst >= (k == 2 ? 0.0001 - 1e-9 : 0));
        CHECK(colour_kept);
    }
    CHECK(records.read_records({buffer.data(), buffer.size()}) == 0);
}

TEST_CASE("survey: the frame is chosen from the set of files, fits 32 bits, and keeps the finest scale") {
    lasmesh::Survey survey;
    SurveyFile a, b;
    a.point_count = b.point_count = 10;
    a.point_format = b.point_format = 3, a.record_length = b.record_length = 34;
    a.scale = {0.01, 0.01, 0.01}, a.offset = {100, 200, 0}, a.min = {100, 200, 0}, a.max = {150, 250, 5};
    b.scale = {0.001, 0.01, 0.01}, b.offset = {90, 200, 0}, b.min = {120, 220, 1}, b.max = {190, 260, 9};
    survey.files = {a, b};
    choose_frame(survey);
    const LasHeader first = survey.header;
    CHECK(first.scale == std::array<double, 3>{0.001, 0.01, 0.01});
    CHECK(first.offset == std::array<double, 3>{90, 200, 0});
    CHECK(first.min == std::array<double, 3>{100, 200, 0});
    CHECK(first.max == std::array<double, 3>{190, 260, 9});
    CHECK(first.point_count == 20);
    std::swap(survey.files[0], survey.files[1]);
    choose_frame(survey);
    CHECK(survey.header.scale == first.scale);
    CHECK(survey.header.offset == first.offset);
    // 40 km at a tenth of a millimetre does not fit 32 bits from the smallest offset: centred.
    survey.files[0].scale[0] = survey.files[1].scale[0] = 0.0001;
    survey.files[0].offset[0] = -200000, survey.files[1].max[0] = 400000;
    choose_frame(survey);
    const double centre = (100.0 + 400000) / 2;
    CHECK(std::abs(survey.header.offset[0] - centre) <= survey.header.scale[0]);
    CHECK((400000 - survey.header.offset[0]) / survey.header.scale[0] < 2147483647.0);
    // Records in one layout: format 2 when a file's format differs (colour kept).
    survey.files[1].point_format = 1, survey.files[1].record_length = 28;
    choose_frame(survey);
    CHECK(survey.header.point_format == 2);
    CHECK(survey.header.point_record_length == 26);
}

TEST_CASE("survey: a bad file stops the run with its name, or with skip_bad_inputs is left out exactly") {
    Split s;
    std::vector<std::string> parts = s.split("part", 4, {s.layout()});
    // part2 ends 100 records early: it fails part-way through its points.
    test::Bytes cut = test::read_file(parts[2]);
    cut.resize(cut.size() - 100 * 34);
    test::write_file(parts[2], cut);
    const std::string junk = s.dir.file("junk.las");
    test::write_file(junk, test::Bytes(500, std::byte{7})); // fails at its header
    std::vector<std::string> inputs = parts;
    inputs.push_back(junk);
    BuildOptions o = s.options("out.ply");
    o.report = s.dir.file("out.json");
    const Error e = error_of(inputs, o);
    CHECK(e.kind() == ErrorKind::input);
    CHECK(contains(e.what(), "junk.las"));
    CHECK(!std::filesystem::exists(s.dir.file("out.ply")));
    inputs.pop_back();
    const Error truncated = error_of(inputs, o);
    CHECK(contains(truncated.what(), "part2.las"));
    CHECK(contains(truncated.what(), "truncated"));
    CHECK(truncated.option() == "skip_bad_inputs"); // the command line names --skip-bad-inputs
    CHECK(!std::filesystem::exists(s.dir.file("out.ply")));
    CHECK(!std::filesystem::exists(s.dir.file("out.json")));

    inputs.push_back(junk);
    o.skip_bad_inputs = true;
    const BuildResult skipped = build_mesh(inputs, o);
    REQUIRE(skipped.report.skipped_inputs.size() == 2);
    CHECK(contains(skipped.report.skipped_inputs[0], "junk.las"));
    CHECK(contains(skipped.report.skipped_inputs[1], "part2.las"));
    CHECK(skipped.report.input_files == 3);
    const test::Bytes report = test::read_file(s.dir.file("out.json"));
    CHECK(contains(std::string(reinterpret_cast<const char*>(report.data()), report.size()), "part2.las"));
    build_mesh(std::vector<std::string>{parts[0], parts[1], parts[3]}, s.options("good.ply"));
    CHECK(test::read_file(s.dir.file("out.ply")) == test::read_file(s.dir.file("good.ply")));
}

// Points [first, first + count) of `scene` written in `layout` (in EPSG:from_epsg), transformed to
// EPSG:to_epsg and stored in a fresh frame (whole units of offset, steps of `scale`), declaring it.
test::Bytes transformed(const lasgen::LasLayout& layout, const lasgen::Scene& scene, std::uint64_t first,
                        std::uint64_t count, int from_epsg, int to_epsg, double scale = 0.001) {
    lasgen::LasLayout out = layout;
    out.epsg = to_epsg;
    test::Bytes las = test::make_las_part(out, scene, first, count);
    const std::size_t head = load_le<std::uint32_t>(las.data() + 96), length = load_le<std::uint16_t>(las.data() + 105);
    std::vector<double> x(count), y(count), z(count);
    for (std::uint64_t i = 0; i < count; ++i) {
        const std::byte* record = las.data() + head + i * length;
        x[i] = load_le<std::int32_t>(record) * layout.scale[0] + layout.offset[0];
        y[i] = load_le<std::int32_t>(record + 4) * layout.scale[1] + layout.offset[1];
        z[i] = load_le<std::int32_t>(record + 8) * layout.scale[2] + layout.offset[2];
    }
    const CrsTransform transform(crs_from_text("EPSG:" + std::to_string(from_epsg)),
                                 crs_from_text("EPSG:" + std::to_string(to_epsg)), "test");
    REQUIRE(transform.apply(x.data(), y.data(), z.data(), count) == count);
    const std::array<const std::vector<double>*, 3> values{&x, &y, &z};
    for (int a = 0; a < 3; ++a) {
        const double lo = *std::min_element(values[a]->begin(), values[a]->end());
        const double hi = *std::max_element(values[a]->begin(), values[a]->end());
        const double step = a < 2 ? scale : 0.001, offset = std::floor(lo);
        store_le<double>(las.data() + 131 + 8 * a, step);
        store_le<double>(las.data() + 155 + 8 * a, offset);
        store_le<double>(las.data() + 179 + 16 * a, hi + step); // max, then min
        store_le<double>(las.data() + 187 + 16 * a, lo - step);
        for (std::uint64_t i = 0; i < count; ++i)
            store_le<std::int32_t>(las.data() + head + i * length + 4 * a,
                                   static_cast<std::int32_t>(std::lround(((*values[a])[i] - offset) / step)));
    }
    return las;
}

TEST_CASE("survey: files in other coordinate systems are transformed into the one most of them declare") {
    Split s;
    lasgen::LasLayout utm31 = s.layout();
    utm31.epsg = 32631;
    const std::string whole = s.dir.file("whole.las");
    test::write_file(whole, test::make_las_part(utm31, s.scene, 0, points));
    std::vector<std::string> parts;
    for (int k = 0; k < 3; ++k) {
        parts.push_back(s.dir.file("utm" + std::to_string(k) + ".las"));
        const std::uint64_t first = points * k / 3, end = points * (k + 1) / 3;
        // The same points, the first third as its writer in the next zone east would store them
        // (first: the CRS most files declare is chosen, not the first file's).
        test::write_file(parts.back(), k > 0 ? test::make_las_part(utm31, s.scene, first, end - first)
                                             : transformed(s.layout(), s.scene, first, end - first, 32631, 32632));
    }
    BuildOptions o = s.options("whole.ply");
    o.simplify.error = 0;
    o.bounds = Bounds{s.scene.min, s.scene.max}; // one grid for both: the transformed bounds are wider
    const BuildResult one = build_mesh(whole, o);
    o.outputs[0].path = s.dir.file("parts.ply");
    const BuildResult all = build_mesh(parts, o);
    REQUIRE(all.mesh);
    CHECK(all.report.crs_recorded == "EPSG:32631");
    CHECK(all.report.points_outside == 0);
    // The round trip through PROJ and the 1 mm steps move points by a millimetre at most.
    const double cell = one.report.grid.cell_size;
    CHECK(mean_distance(*all.mesh, *one.mesh) <= 0.02 * cell);
    CHECK(mean_distance(*one.mesh, *all.mesh) <= 0.02 * cell);
    std::reverse(parts.begin(), parts.end());
    o.outputs[0].path = s.dir.file("reversed.ply");
    build_mesh(parts, o);
    CHECK(test::read_file(s.dir.file("reversed.ply")) == test::read_file(s.dir.file("parts.ply")));
    // Asked for the other zone: every file transformed, the mesh recorded in it.
    o.crs = "EPSG:32632";
    o.bounds.reset();
    o.outputs[0].path = s.dir.file("zone32.ply");
    const BuildResult zone32 = build_mesh(parts, o);
    CHECK(zone32.report.crs_recorded == "EPSG:32632");
    CHECK(zone32.report.points_outside == 0);
    // The grid centred on the scene's centre as PROJ puts it in zone 32 (within a metre: the grid
    // covers the transformed box, turned by the grid convergence).
    double x = (s.scene.min[0] + s.scene.max[0]) / 2, y = (s.scene.min[1] + s.scene.max[1]) / 2, z = 0;
    CrsTransform(crs_from_text("EPSG:32631"), crs_from_text("EPSG:32632"), "test").apply(&x, &y, &z, 1);
    const GridSpec& grid = zone32.report.grid;
    CHECK(std::abs(grid.origin[0] + grid.dims[0] * grid.cell_size / 2 - x) < 1);
    CHECK(std::abs(grid.origin[1] + grid.dims[1] * grid.cell_size / 2 - y) < 1);
    // A geographic CRS asked for is refused: cells must be cubes.
    o.crs = "EPSG:4326";
    o.outputs[0].path = s.dir.file("degrees.ply");
    CHECK(error_of(parts, o).option() == "crs");
}

TEST_CASE("survey: files without a CRS are taken to be in the others'; an input given twice, or standard input "
          "among several, refused") {
    Split s;
    std::vector<lasgen::LasLayout> layouts(3, s.layout());
    layouts[0].epsg = layouts[1].epsg = 32631;
    std::vector<std::string> parts = s.split("utm", 3, layouts); // the third declares none
    const BuildResult result = build_mesh(parts, s.options("utm.ply"));
    CHECK(result.report.crs_recorded == "EPSG:32631");
    CHECK(std::any_of(result.report.warnings.begin(), result.report.warnings.end(), [](const std::string& w) {
        return contains(w, "declare no coordinate system") && contains(w, "utm2.las");
    }));
    layouts[2].epsg = 32767; // user-defined: PROJ cannot build it from the keys, nor transform it
    parts = s.split("mixed", 3, layouts);
    BuildOptions o = s.options("mixed.ply");
    const Error e = error_of(parts, o);
    CHECK(e.kind() == ErrorKind::input);
    CHECK(contains(e.what(), "mixed2.las"));
    CHECK(contains(e.what(), "cannot be transformed"));
    CHECK(error_of({parts[0], parts[1], parts[0]}, o).kind() == ErrorKind::usage);
    CHECK(error_of({parts[0], "-"}, o).kind() == ErrorKind::usage);
    CHECK(!std::filesystem::exists(s.dir.file("mixed.ply")));
}

TEST_CASE("survey: a file in longitude and latitude is meshed in metres, in the UTM zone of its centre") {
    Split s;
    lasgen::LasLayout utm31 = s.layout();
    utm31.epsg = 32631;
    const std::string metres = s.dir.file("metres.las"), degrees = s.dir.file("degrees.las");
    test::write_file(metres, test::make_las_part(utm31, s.scene, 0, points));
    // The same points in WGS 84 longitude and latitude, in steps of 1e-8 degree (1 mm and less).
    test::write_file(degrees, transformed(s.layout(), s.scene, 0, points, 32631, 4326, 1e-8));
    BuildOptions o = s.options("metres.ply");
    o.simplify.error = 0;
    const BuildResult one = build_mesh(metres, o);
    o.outputs[0].path = s.dir.file("degrees.ply");
    o.bounds = Bounds{s.scene.min, s.scene.max}; // the grid of the file in metres
    const BuildResult projected = build_mesh(degrees, o);
    REQUIRE(projected.mesh);
    CHECK(projected.report.crs_recorded == "EPSG:32631");
    CHECK(contains(projected.report.crs, "projected from WGS 84 (EPSG:4326)"));
    CHECK(read_mesh(s.dir.file("degrees.ply")).crs == "EPSG:32631");
    CHECK(projected.report.points_outside == 0);
    const double cell = one.report.grid.cell_size;
    CHECK(mean_distance(*projected.mesh, *one.mesh) <= 0.02 * cell);
    CHECK(mean_distance(*one.mesh, *projected.mesh) <= 0.02 * cell);
    // compare brings the cloud in degrees into the mesh's CRS: distances in metres, as close as
    // the mesh of the file in metres is to its cloud.
    LasReader cloud(degrees), cloud_in_metres(metres);
    const CompareResult measured = compare(*projected.mesh, cloud, CompareOptions{});
    const CompareResult reference = compare(*one.mesh, cloud_in_metres, CompareOptions{});
    CHECK(contains(measured.cloud_transformed, "WGS 84 (EPSG:4326)"));
    CHECK(reference.cloud_transformed.empty());
    CHECK(measured.cloud_to_mesh.within_1_cell >= 0.99);
    CHECK(std::abs(measured.cloud_to_mesh.mean - reference.cloud_to_mesh.mean) <= 0.02 * cell);
}
