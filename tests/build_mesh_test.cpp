// SPDX-License-Identifier: Apache-2.0
// build_mesh as a library call, with no command line in front of it: its own checks on the
// options (before anything is read), what it writes (every output or none, the report with
// them), and its errors' kinds and the option each names.
#include "lasmesh/build_mesh.hpp"
#include "lasmesh/error.hpp"

#include <doctest/doctest.h>

#include "build_steps.hpp"
#include "grid/cell_sums.hpp"
#include "test_support.hpp"

#include <algorithm>
#include <cstdio>
#include <fcntl.h>
#include <filesystem>
#include <limits>
#include <thread>
#include <unistd.h>

using namespace lasmesh;

namespace {

// The error build_mesh throws, or a failed check when it throws none.
Error error_of(const std::string& input, const BuildOptions& options) {
    try {
        build_mesh(input, options);
    } catch (const Error& e) {
        return e;
    }
    FAIL("no error");
    return Error(ErrorKind::usage, "");
}

using test::contains;

OutputRequest request(const std::string& path, std::optional<MeshFormat> format = std::nullopt) {
    OutputRequest output;
    output.path = path;
    output.format = format;
    return output;
}

// A small deck scan, and options that mesh it quickly.
struct Fixture {
    test::TempDir dir;
    std::string input = dir.file("deck.las");
    Fixture() {
        lasgen::SceneOptions scene;
        scene.origin = {0, 0, 0};
        test::write_file(input, test::make_las(lasgen::LasLayout{}, lasgen::make_scene(scene), 60000, 3));
    }
    BuildOptions options(const std::vector<std::string>& outputs) const {
        BuildOptions o;
        o.grid = GridRequest::longest(64);
        for (const std::string& name : outputs) o.outputs.push_back(request(dir.file(name)));
        return o;
    }
};

} // namespace

TEST_CASE("build_mesh: each output's format from its extension unless given; the report beside them") {
    Fixture f;
    BuildOptions o = f.options({"a.glb", "a.drc", "a.ply"});
    o.outputs.push_back(request(f.dir.file("forced.bin"), MeshFormat::ply));
    o.report = f.dir.file("report.json");
    const BuildResult result = build_mesh(f.input, o);
    CHECK(result.report.triangles > 1000);
    const auto head = [](const std::string& path, std::size_t n) {
        const test::Bytes bytes = test::read_file(path);
        return std::string(reinterpret_cast<const char*>(bytes.data()), std::min(n, bytes.size()));
    };
    CHECK(head(f.dir.file("a.glb"), 4) == "glTF");
    CHECK(head(f.dir.file("a.drc"), 5) == "DRACO");
    CHECK(head(f.dir.file("a.ply"), 3) == "ply");
    CHECK(head(f.dir.file("forced.bin"), 3) == "ply");
    const std::string report = head(f.dir.file("report.json"), 1 << 20);
    CHECK(contains(report, "\"triangles\":" + std::to_string(result.report.triangles)));
    CHECK(contains(report, "\"path\":\"" + f.dir.file("a.glb") + "\""));
    CHECK(!contains(report, "placement")); // the sheet has no vertex placement to report
}

TEST_CASE("build_mesh: its own checks, before the input is read") {
    Fixture f;
    const std::string missing = f.dir.file("missing.las"); // never opened: the checks come first
    SUBCASE("no output") {
        const Error e = error_of(missing, f.options({}));
        CHECK(e.kind() == ErrorKind::usage);
        CHECK(e.option() == "outputs");
    }
    SUBCASE("an unknown extension") {
        const Error e = error_of(missing, f.options({"x.obj"}));
        CHECK(e.kind() == ErrorKind::usage);
        CHECK(e.option() == "outputs");
        CHECK(contains(e.what(), "x.obj\": unknown extension"));
    }
    SUBCASE("a missing output folder") {
        BuildOptions o = f.options({});
        o.outputs.push_back(request(f.dir.file("no/such/x.ply")));
        CHECK(error_of(missing, o).kind() == ErrorKind::output);
    }
    SUBCASE("an output over the input, over another output, or the report over one") {
        BuildOptions over_input = f.options({});
        over_input.outputs.push_back(request(f.input, MeshFormat::ply));
        const Error e = error_of(f.input, over_input);
        CHECK(e.kind() == ErrorKind::usage);
        CHECK(contains(e.what(), "are the same file"));
        BuildOptions twice = f.options({"x.ply", "./x.ply"});
        CHECK(contains(error_of(f.input, twice).what(), "are the same file"));
        BuildOptions report = f.options({"x.ply"});
        report.report = f.dir.file("x.ply");
        CHECK(contains(error_of(f.input, report).what(), "the report"));
        CHECK(test::read_file(f.input).size() > 60000 * 20); // the input untouched
    }
    SUBCASE("standard input redirected from the output's file") {
        test::write_file(f.dir.file("in.ply"), test::read_file(f.input));
        const int saved = ::dup(STDIN_FILENO);
        const int file = ::open(f.dir.file("in.ply").c_str(), O_RDONLY);
        REQUIRE(file >= 0);
        ::dup2(file, STDIN_FILENO);
        ::close(file);
        std::string message;
        try {
            build_mesh("-", f.options({"in.ply"}));
        } catch (const Error& e) {
            message = e.what();
        }
        ::dup2(saved, STDIN_FILENO);
        ::close(saved);
        CHECK(contains(message, "are the same file"));
        CHECK(test::read_file(f.dir.file("in.ply")) == test::read_file(f.input));
    }
    SUBCASE("options that make no sense") {
        const auto option_of = [&](const BuildOptions& o) {
            const Error e = error_of(missing, o);
            CHECK(e.kind() == ErrorKind::usage);
            return e.option();
        };
        BuildOptions o = f.options({"x.ply"});
        o.placement = VertexPlacement::iso; // the sheet has none
        CHECK(option_of(o) == "placement");
        o = f.options({"x.ply"});
        o.iso = -1;
        CHECK(option_of(o) == "iso");
        o = f.options({"x.ply"});
        o.simplify.error = std::numeric_limits<double>::quiet_NaN();
        CHECK(option_of(o) == "simplify");
        o = f.options({"x.ply"});
        o.min_piece = {2, true}; // 200% of the diagonal
        CHECK(option_of(o) == "min_piece");
        o = f.options({"x.ply"});
        o.threads = -1;
        CHECK(option_of(o) == "threads");
        o = f.options({"x.ply"});
        o.scan_bounds = true; // standard input cannot be read twice
        const Error e = error_of("-", o);
        CHECK(e.option() == "scan_bounds");
    }
}

TEST_CASE("build_mesh: an empty mesh is an error, and nothing is written") {
    Fixture f;
    BuildOptions o = f.options({"e.ply", "e.glb"});
    o.min_piece = {1e9, false};
    o.report = f.dir.file("e.json");
    const Error e = error_of(f.input, o);
    CHECK(e.kind() == ErrorKind::input);
    CHECK(e.option() == "min_piece");
    CHECK(contains(e.what(), "the mesh is empty, nothing written"));
    for (const char* name : {"e.ply", "e.glb", "e.json"}) CHECK(!std::filesystem::exists(f.dir.file(name)));
}

TEST_CASE("refine_thin by default: with the automatic grid, from files, when its cells hold a median of 12 or more") {
    Fixture f;
    CellGrid grid;
    grid.cells.resize(101);
    for (std::size_t k = 0; k < grid.cells.size(); ++k) grid.cells[k].count = k < 50 ? 11 : 12; // median 12
    const auto decide = [&](const std::string& input, const BuildOptions& o) {
        RunReport r;
        const bool refined = refines_thin_parts({f.input, input}, o, grid.median_count(), r);
        return std::pair{refined, r.thin_unrefined};
    };
    const BuildOptions defaults;
    CHECK(decide(f.input, defaults) == std::pair{true, std::string()});
    CHECK(!decide("-", defaults).first);
    CHECK(decide("-", defaults).second == "standard input cannot be read twice: save it to a file to refine them");
    BuildOptions closed;
    closed.surface = SurfaceKind::closed;
    CHECK(!decide(f.input, closed).first);
    CHECK(contains(decide(f.input, closed).second, "the closed surface"));
    BuildOptions given;
    given.grid = GridRequest::longest(64);
    CHECK(!decide(f.input, given).first);
    CHECK(contains(decide(f.input, given).second, "a grid was asked for"));
    given.refine_thin = ThinRefinement::always;
    CHECK(decide(f.input, given) == std::pair{true, std::string()});
    BuildOptions never;
    never.refine_thin = ThinRefinement::never;
    CHECK(decide(f.input, never) == std::pair{false, std::string()});
    grid.cells[50].count = 11; // median 11
    CHECK(!decide(f.input, defaults).first);
    CHECK(decide(f.input, defaults).second ==
          "the points are too sparse for half cells (a median of 11 in an occupied cell, 12 needed)");
}

TEST_CASE("refine_thin by default: a grid asked for meshes at its cell, the report says why; asked for, refined") {
    Fixture f;
    const auto mesh = [&](ThinRefinement refine, SurfaceKind surface = SurfaceKind::sheet) {
        BuildOptions o = f.options({"m.ply"});
        o.refine_thin = refine, o.surface = surface;
        const BuildResult result = build_mesh(f.input, o);
        return std::pair{result.report, test::read_file(f.dir.file("m.ply"))};
    };
    const auto [given, given_bytes] = mesh(ThinRefinement::automatic);
    CHECK(given.median_count >= 12); // dense enough: it is the grid asked for that keeps one cell
    CHECK(given.thin_cells == 0);
    CHECK(contains(given.thin_unrefined, "a grid was asked for"));
    CHECK(given_bytes == mesh(ThinRefinement::never).second);
    const auto [refined, refined_bytes] = mesh(ThinRefinement::always);
    CHECK(refined.thin_cells > 0);
    CHECK(refined_bytes != given_bytes);
    const auto [closed, closed_bytes] = mesh(ThinRefinement::automatic, SurfaceKind::closed);
    CHECK(contains(closed.thin_unrefined, "the closed surface"));
    CHECK(closed_bytes == mesh(ThinRefinement::never, SurfaceKind::closed).second);
    BuildOptions asked = f.options({"m.ply"});
    asked.refine_thin = ThinRefinement::always, asked.surface = SurfaceKind::closed;
    CHECK(error_of(f.input, asked).option() == "refine_thin");
}

TEST_CASE("refine_thin by default, end to end: refined in one call, from an accumulation and by a merge") {
    Fixture f;
    // A ball 400 m from the deck stretches the automatic grid's cells: 16 points in the median
    // occupied cell, denser than the grid.
    lasgen::SceneOptions far;
    far.kind = lasgen::SceneKind::sphere, far.size = 1, far.origin = {400, 0, 0};
    const std::string ball = f.dir.file("ball.las");
    test::write_file(ball, test::make_las(lasgen::LasLayout{}, lasgen::make_scene(far), 300, 5));
    const std::vector<std::string> inputs{f.input, ball};
    const auto mesh = [&](ThinRefinement refine, const std::string& name) {
        BuildOptions o;
        o.refine_thin = refine;
        o.outputs.push_back(request(f.dir.file(name)));
        return build_mesh(inputs, o).report;
    };
    const RunReport automatic = mesh(ThinRefinement::automatic, "auto.ply");
    CHECK(automatic.median_count >= 12);
    CHECK(automatic.thin_cells > 0);
    CHECK(automatic.thin_unrefined.empty());
    mesh(ThinRefinement::always, "always.ply");
    mesh(ThinRefinement::never, "never.ply");
    const test::Bytes refined = test::read_file(f.dir.file("auto.ply"));
    CHECK(refined == test::read_file(f.dir.file("always.ply")));
    CHECK(refined != test::read_file(f.dir.file("never.ply")));

    BuildOptions o;
    o.outputs.push_back(request(f.dir.file("again.ply")));
    const AccumulatedInputs read = accumulate_inputs(inputs, o);
    CHECK(build_mesh(read, o).report.thin_cells == automatic.thin_cells);
    CHECK(test::read_file(f.dir.file("again.ply")) == refined);

    TilePlan plan = plan_tiles(inputs, o, 0);
    write_plan(plan, f.dir.file("p.plan.json"));
    const TilePlan planned = read_plan(f.dir.file("p.plan.json"));
    for (std::size_t k = 0; k < planned.tiles.size(); ++k) run_tile(planned, k, o);
    o.outputs = {request(f.dir.file("merged.ply"))};
    CHECK(merge_tiles(planned, o).report.thin_cells == automatic.thin_cells);
    CHECK(test::read_file(f.dir.file("merged.ply")) == refined);
}

TEST_CASE("refine_thin: read alongside the extraction or alone first (under a memory limit), the same bytes; a "
          "second read that fails stops the run, nothing written") {
    Fixture f;
    BuildOptions o = f.options({"alongside.ply"});
    o.refine_thin = ThinRefinement::always;
    // The observer hears the read, from the calling thread only.
    struct Threads : BuildObserver {
        std::vector<std::thread::id> callers;
        std::vector<std::string> said;
        void stage_started(BuildStage, const std::string& what) override {
            callers.push_back(std::this_thread::get_id()), said.push_back(what);
        }
        void detail(const std::string& line) override {
            callers.push_back(std::this_thread::get_id()), said.push_back(line);
        }
    } watch_threads;
    const RunReport alongside = build_mesh(f.input, o, &watch_threads).report;
    REQUIRE(alongside.thin_cells > 0);
    CHECK(alongside.thin_read > 0);
    CHECK(std::count(watch_threads.callers.begin(), watch_threads.callers.end(), std::this_thread::get_id()) ==
          static_cast<std::ptrdiff_t>(watch_threads.callers.size()));
    CHECK(std::count(watch_threads.said.begin(), watch_threads.said.end(), "reading the thin parts again") == 1);
    CHECK(std::any_of(watch_threads.said.begin(), watch_threads.said.end(),
                      [](const std::string& line) { return line.starts_with("thin parts "); }));
    BuildOptions limited = f.options({"first.ply"});
    limited.refine_thin = ThinRefinement::always;
    limited.max_memory = std::uint64_t{16} << 30; // any limit: the second read comes first then
    const RunReport first = build_mesh(f.input, limited).report;
    CHECK(first.thin_cells == alongside.thin_cells);
    CHECK(first.read_accumulate >= first.thin_read);
    CHECK(test::read_file(f.dir.file("first.ply")) == test::read_file(f.dir.file("alongside.ply")));

    // The input cut short once the first read ends: the second read's error, from its thread,
    // is the run's, and no output appears.
    struct CutInput : BuildObserver {
        std::string path;
        void stage_ended(BuildStage stage, const RunReport&) override {
            if (stage == BuildStage::read_accumulate) std::filesystem::resize_file(path, 4000);
        }
    };
    const std::string cut = f.dir.file("cut.las");
    std::filesystem::copy_file(f.input, cut);
    CutInput watch;
    watch.path = cut;
    BuildOptions again = f.options({"cut.ply"});
    again.refine_thin = ThinRefinement::always;
    try {
        build_mesh(cut, again, &watch);
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::input);
        CHECK(contains(e.what(), cut));
    }
    CHECK(!std::filesystem::exists(f.dir.file("cut.ply")));
}

TEST_CASE("accumulate_inputs with refine_thin: one call's bytes, the thin parts read again once an iso") {
    Fixture f;
    BuildOptions o = f.options({});
    o.refine_thin = ThinRefinement::always;
    const AccumulatedInputs read = accumulate_inputs({f.input}, o);
    struct ThinReads : BuildObserver {
        int reads = 0;
        void stage_started(BuildStage, const std::string& what) override {
            reads += what == "reading the thin parts again";
        }
    };
    struct Variant {
        ThinRefinement refine;
        double simplify;
        std::optional<double> iso;
    };
    // The second re-uses the first's thin parts (the same iso); the third reads them for its
    // own; the fourth, unrefined, must not start from a refined surface kept from the third.
    const std::vector<Variant> variants = {{ThinRefinement::always, 0.5, std::nullopt},
                                           {ThinRefinement::always, 0.25, std::nullopt},
                                           {ThinRefinement::always, 0.25, 2.0},
                                           {ThinRefinement::never, 0.25, 2.0}};
    const std::vector<int> reads_after = {1, 1, 2, 2};
    ThinReads watch;
    std::vector<test::Bytes> again;
    std::vector<std::uint64_t> thin_cells;
    for (const Variant& v : variants) {
        BuildOptions m = f.options({"again.ply"});
        m.refine_thin = v.refine, m.simplify.error = v.simplify, m.iso = v.iso;
        thin_cells.push_back(build_mesh(read, m, &watch).report.thin_cells);
        again.push_back(test::read_file(f.dir.file("again.ply")));
        CHECK(watch.reads == reads_after[again.size() - 1]);
    }
    for (std::size_t k = 0; k < variants.size(); ++k) {
        CAPTURE(k);
        BuildOptions m = f.options({"once.ply"});
        m.refine_thin = variants[k].refine, m.simplify.error = variants[k].simplify, m.iso = variants[k].iso;
        const BuildResult once = build_mesh(f.input, m);
        CHECK(test::read_file(f.dir.file("once.ply")) == again[k]);
        CHECK(once.report.thin_cells == thin_cells[k]);
    }
    CHECK(thin_cells[0] > 0); // there are thin parts, and refining them changes the mesh
    CHECK(thin_cells[3] == 0);
    CHECK(again[2] != again[3]);
}

TEST_CASE("accumulate_inputs, then build_mesh of it: the bytes of one build_mesh call, without a re-read") {
    Fixture f;
    // The accumulation's copy of the input is removed before meshing: a re-read would fail.
    const std::string input = f.dir.file("moved.las");
    std::filesystem::copy_file(f.input, input);
    BuildOptions o = f.options({});
    const AccumulatedInputs read = accumulate_inputs({input}, o);
    CHECK(read.report.points_read == 60000);
    CHECK(read.report.triangles == 0); // nothing meshed yet
    struct Variant {
        double simplify;
        SurfaceKind surface;
        std::optional<double> iso;
    };
    // The second starts from the first's surface (only the simplification differs).
    const std::vector<Variant> variants = {{0.5, SurfaceKind::sheet, std::nullopt},
                                           {0.25, SurfaceKind::sheet, std::nullopt},
                                           {0.25, SurfaceKind::sheet, 2.0},
                                           {0, SurfaceKind::closed, std::nullopt}};
    struct Details : BuildObserver {
        std::string text;
        void detail(const std::string& line) override { text += line + "\n"; }
    };
    std::vector<std::string> details;
    std::vector<std::vector<test::Bytes>> again(variants.size());
    std::filesystem::rename(input, input + ".away");
    for (std::size_t k = 0; k < variants.size(); ++k) {
        BuildOptions m = f.options({"again.ply", "again.glb", "again.html"});
        m.simplify.error = variants[k].simplify;
        m.surface = variants[k].surface;
        m.iso = variants[k].iso;
        Details watch;
        const BuildResult result = build_mesh(read, m, &watch);
        details.push_back(watch.text);
        CHECK(result.report.points_read == 60000);
        for (const char* name : {"again.ply", "again.glb", "again.html"})
            again[k].push_back(test::read_file(f.dir.file(name)));
    }
    std::filesystem::rename(input + ".away", input);
    for (std::size_t k = 0; k < variants.size(); ++k) {
        CAPTURE(k);
        BuildOptions m = f.options({"once.ply", "once.glb", "once.html"});
        m.simplify.error = variants[k].simplify;
        m.surface = variants[k].surface;
        m.iso = variants[k].iso;
        build_mesh(input, m);
        std::size_t i = 0;
        for (const char* name : {"once.ply", "once.glb", "once.html"})
            CHECK(test::read_file(f.dir.file(name)) == again[k][i++]);
    }
    CHECK(again[0][0] != again[1][0]); // the options did change the mesh
    CHECK(again[1][0] != again[2][0]);
    const std::string reused = "the accumulation's surface re-used";
    CHECK(!contains(details[0], reused));
    CHECK(contains(details[1], reused)); // the same surface, simplified less
    CHECK(!contains(details[2], reused));
    CHECK(!contains(details[3], reused));

    // Options that would read differently are refused, not silently ignored.
    BuildOptions other = f.options({"x.ply"});
    other.grid = GridRequest::longest(32);
    try {
        build_mesh(read, other);
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(e.kind() == ErrorKind::usage);
        CHECK(e.option() == "grid");
    }
    CHECK(!std::filesystem::exists(f.dir.file("x.ply")));
}

TEST_CASE("build_mesh: a grid longer than 4,096 cells (a 45 m strip at 1 cm): meshed along its whole length, on its "
          "plane") {
    // A strip 45 m by 5 cm at z 0.05, 8 points a square centimetre: 4,501 cells along x.
    test::TempDir dir;
    std::vector<lasgen::GeneratedPoint> points;
    for (int i = 0; i < 4500 * 5 * 8; ++i) {
        const double x = 0.01 * (i / 40) + 0.0025 * (i % 4), y = 0.001 * (i % 40) + 0.005;
        points.push_back({{x, y, 0.05}, {120, 120, 120}, 1});
    }
    const std::string input = dir.file("strip.las");
    test::write_file(input, test::las_with_points(points, {0, 0, 0}, {45, 0.05, 0.1}, 8, 3, 0.0001));
    BuildOptions options;
    options.grid = GridRequest::cell_edge(0.01);
    options.keep_mesh = true;
    options.refine_thin = ThinRefinement::never;
    const BuildResult result = build_mesh(input, options);
    CHECK(result.report.grid.dims[0] > 4096);
    REQUIRE(result.mesh);
    const Mesh& m = *result.mesh;
    REQUIRE(!m.positions.empty());
    double low = 1e9, high = -1e9, off = 0;
    for (const auto& p : m.positions) {
        const double x = p[0] + m.origin[0], z = p[2] + m.origin[2];
        low = std::min(low, x), high = std::max(high, x);
        off = std::max(off, std::abs(z - 0.05));
    }
    CHECK(low < 0.02);
    CHECK(high > 44.98);
    CHECK(off < 0.002);
}
