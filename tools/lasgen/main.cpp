// SPDX-License-Identifier: Apache-2.0
// lasgen: writes a synthetic LAS scene of any size to a file or standard output, streamed in
// batches (memory does not grow with the point count) and deterministic for a seed.
#include "las_writer.hpp"
#include "scene.hpp"
#include "truth.hpp"

#include "lasmesh/mesh_files.hpp"

#include <CLI/CLI.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace {

struct Options {
    std::string scene = "deck";
    std::uint64_t points = 1'000'000;
    std::uint64_t seed = 1;
    std::string version = "1.2";
    int format = 3;
    int extra_bytes = 0;
    int color_depth = 8;
    double noise = -1;
    double size = 10;
    double scale = 0.001;
    int epsg = 0;
    std::vector<double> origin;
    std::vector<int> color;
    std::string output = "-";
    std::string order = "random";
    std::uint32_t split = 1;         // write the points into this many files
    bool split_vary = false;         // each file of a split its own offset, scale and point format
    std::uint32_t split_xy = 0;      // write the points into N x N files by their x and y
    std::string measure;             // measure this mesh against the scene's true surfaces instead
    std::string json;                // and write the measurement as JSON here too
    std::vector<double> within;      // and measure only the true surfaces in this world box
    std::size_t samples = 1'000'000; // points spread over the mesh, and over the true surfaces
};

// A Morton (Z-order) key of a position on a 2 cm lattice: points close in space get close keys.
std::uint64_t morton_key(const lasmesh::Vec3& p, const lasmesh::Vec3& min) {
    std::uint64_t key = 0;
    std::uint32_t q[3];
    for (int a = 0; a < 3; ++a) q[a] = static_cast<std::uint32_t>(std::clamp((p[a] - min[a]) / 0.02, 0.0, 2097151.0));
    for (int bit = 20; bit >= 0; --bit)
        for (int a = 2; a >= 0; --a) key = (key << 1) | ((q[a] >> bit) & 1);
    return key;
}

void write_all(std::FILE* out, const std::byte* data, std::size_t size, const std::string& name) {
    if (std::fwrite(data, 1, size, out) != size)
        throw std::runtime_error("cannot write " + name + ": " + std::strerror(errno));
}

// Points [first_index, first_index + count_all) of the scene as one LAS file.
void write_points(const Options& o, const lasgen::Scene& scene, const lasgen::LasLayout& layout,
                  std::uint64_t first_index, std::uint64_t count_all, const std::string& output) {
    // Quantisation moves a point by up to half a step: widen the bounds by one step.
    lasmesh::Vec3 min = scene.min, max = scene.max;
    for (int a = 0; a < 3; ++a) min[a] -= o.scale, max[a] += o.scale;

    std::ostringstream description;
    description << "scene=" << scene.name << " points=" << o.points << " seed=" << o.seed;
    if (o.split > 1) description << " part=" << first_index << "+" << count_all;
    const auto head = lasgen::las_file_head(layout, count_all, min, max, description.str());

    std::FILE* out = output == "-" ? stdout : std::fopen(output.c_str(), "wb");
    if (!out) throw std::runtime_error("cannot create " + output + ": " + std::strerror(errno));
    const std::string name = output == "-" ? "standard output" : output;
    write_all(out, head.data(), head.size(), name);

    const std::size_t length = lasgen::record_length(layout);
    // 2^18 records a batch, fewer when records are long (at most 32 MiB of them) or fewer are
    // asked for: --extra-bytes 65501 took 17 GB for 100 points. (Scan order sorts each batch, so
    // batches stay 2^18 points for records up to 128 bytes: those files are unchanged.)
    const std::uint64_t batch = std::max<std::uint64_t>(
        1,
        std::min<std::uint64_t>({std::uint64_t{1} << 18, (32u << 20) / length, std::max<std::uint64_t>(1, count_all)}));
    std::vector<std::byte> buffer(batch * length);
    std::vector<lasgen::GeneratedPoint> points(batch);
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(batch);
    const bool scan_order = o.order == "scan";
    for (std::uint64_t first = first_index; first < first_index + count_all; first += batch) {
        const std::size_t count = static_cast<std::size_t>(std::min(batch, first_index + count_all - first));
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                points[i] = lasgen::generate_point(scene, o.seed, first + i);
                keys[i] = {scan_order ? morton_key(points[i].position, scene.min) : 0, static_cast<std::uint32_t>(i)};
            }
        });
        // Scan order imitates a scanner's acquisition order: each batch of points sorted along a
        // space-filling curve, so consecutive records lie centimetres apart.
        if (scan_order) std::sort(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(count));
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i)
                lasgen::encode_record(layout, points[keys[i].second], first + i, buffer.data() + i * length);
        });
        write_all(out, buffer.data(), count * length, name);
    }
    if (std::fflush(out) != 0 || (out != stdout && std::fclose(out) != 0))
        throw std::runtime_error("cannot write " + name + ": " + std::strerror(errno));
}

// The points into n x n files by where they lie in x and y (a survey delivered in map tiles), each
// file's header bounds those of its own points: NAME-X_Y.las. Every file is open at once; each
// header is written again at the end with its count and bounds.
void write_points_by_area(const Options& o, const lasgen::Scene& scene, const lasgen::LasLayout& layout,
                          const std::string& output) {
    const std::uint32_t n = o.split_xy;
    const std::string stem = output.substr(0, output.rfind('.')), ext = output.substr(stem.size());
    struct Part {
        std::FILE* file = nullptr;
        std::string name;
        std::uint64_t count = 0;
        lasmesh::Vec3 min{INFINITY, INFINITY, INFINITY}, max{-INFINITY, -INFINITY, -INFINITY};
    };
    std::vector<Part> parts(std::size_t{n} * n);
    const std::string description =
        "scene=" + scene.name + " points=" + std::to_string(o.points) + " seed=" + std::to_string(o.seed);
    const auto head_of = [&](const Part& part) {
        lasmesh::Vec3 min = part.min, max = part.max;
        for (int a = 0; a < 3; ++a) {
            if (part.count == 0) min[a] = max[a] = scene.min[a];
            min[a] -= o.scale, max[a] += o.scale;
        }
        return lasgen::las_file_head(layout, part.count, min, max, description);
    };
    for (std::uint32_t y = 0; y < n; ++y)
        for (std::uint32_t x = 0; x < n; ++x) {
            Part& part = parts[y * n + x];
            part.name = stem + "-" + std::to_string(x) + "_" + std::to_string(y) + ext;
            part.file = std::fopen(part.name.c_str(), "wb");
            if (!part.file) throw std::runtime_error("cannot create " + part.name + ": " + std::strerror(errno));
            const auto head = head_of(part);
            write_all(part.file, head.data(), head.size(), part.name);
        }
    const std::size_t length = lasgen::record_length(layout);
    const std::uint64_t batch = std::uint64_t{1} << 18;
    std::vector<lasgen::GeneratedPoint> points(batch);
    std::vector<std::byte> record(length);
    for (std::uint64_t first = 0; first < o.points; first += batch) {
        const std::size_t count = static_cast<std::size_t>(std::min(batch, o.points - first));
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const auto& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i)
                points[i] = lasgen::generate_point(scene, o.seed, first + i);
        });
        for (std::size_t i = 0; i < count; ++i) {
            const lasmesh::Vec3& p = points[i].position;
            std::uint32_t at[2];
            for (int a = 0; a < 2; ++a)
                at[a] = static_cast<std::uint32_t>(std::clamp(
                    std::floor((p[a] - scene.min[a]) / (scene.max[a] - scene.min[a]) * n), 0.0, double(n - 1)));
            Part& part = parts[at[1] * n + at[0]];
            lasgen::encode_record(layout, points[i], first + i, record.data());
            write_all(part.file, record.data(), length, part.name);
            ++part.count;
            for (int a = 0; a < 3; ++a)
                part.min[a] = std::min(part.min[a], p[a]), part.max[a] = std::max(part.max[a], p[a]);
        }
    }
    for (Part& part : parts) {
        const auto head = head_of(part);
        if (std::fseek(part.file, 0, SEEK_SET) != 0) throw std::runtime_error("cannot seek in " + part.name);
        write_all(part.file, head.data(), head.size(), part.name);
        if (std::fclose(part.file) != 0)
            throw std::runtime_error("cannot write " + part.name + ": " + std::strerror(errno));
    }
}

void generate(const Options& o) {
    lasgen::SceneOptions scene_options;
    scene_options.kind = lasgen::parse_scene_kind(o.scene);
    scene_options.size = o.size;
    scene_options.noise = o.noise;
    if (!o.origin.empty())
        scene_options.origin = {o.origin[0], o.origin[1], o.origin[2]};
    else if (scene_options.kind == lasgen::SceneKind::deck)
        scene_options.origin = {431250.0, 6700200.0, 10.0}; // UTM-like: large coordinates on purpose
    if (!o.color.empty())
        for (int c = 0; c < 3; ++c) scene_options.color[c] = static_cast<std::uint8_t>(o.color[c]);
    const lasgen::Scene scene = lasgen::make_scene(scene_options);
    if (!o.measure.empty()) {
        lasgen::TruthOptions truth;
        truth.within = o.within;
        truth.mesh_samples = truth.truth_samples = o.samples;
        const lasgen::TruthReport report = lasgen::measure_against_truth(scene, lasmesh::read_mesh(o.measure), truth);
        std::cout << lasgen::truth_table(report, truth);
        if (!o.json.empty()) {
            std::ofstream out(o.json);
            out << lasgen::truth_json(report, truth);
            if (!out.flush()) throw std::runtime_error("cannot write " + o.json + ": " + std::strerror(errno));
        }
        return;
    }

    lasgen::LasLayout layout;
    if (o.version.size() != 3 || o.version.compare(0, 2, "1.") != 0 || o.version[2] < '0' || o.version[2] > '4')
        throw std::invalid_argument("version must be 1.0, 1.1, 1.2, 1.3 or 1.4");
    layout.version_minor = o.version[2] - '0';
    layout.point_format = o.format;
    layout.extra_bytes = o.extra_bytes;
    layout.color_bits = o.color_depth;
    layout.scale = {o.scale, o.scale, o.scale};
    layout.epsg = o.epsg;
    for (int a = 0; a < 3; ++a) layout.offset[a] = std::floor(scene.min[a]);
    if (o.split_xy > 0) {
        if (o.output == "-") throw std::invalid_argument("--split-xy writes files: give -o NAME.las");
        write_points_by_area(o, scene, layout, o.output);
        return;
    }
    if (o.split <= 1) {
        write_points(o, scene, layout, 0, o.points, o.output);
        return;
    }
    // A survey delivered as several files: file k holds points [k n / N, (k + 1) n / N) of the
    // single file, so together they hold exactly its points.
    if (o.output == "-") throw std::invalid_argument("--split writes files: give -o NAME.las");
    const std::string path = o.output, stem = path.substr(0, path.rfind('.')), ext = path.substr(stem.size());
    const std::size_t width = std::to_string(o.split - 1).size();
    for (std::uint32_t k = 0; k < o.split; ++k) {
        lasgen::LasLayout file = layout;
        if (o.split_vary) { // a whole number of metres apart, and every third file in another format
            for (int a = 0; a < 3; ++a) file.offset[a] += k % 7;
            if (k % 2 == 1) file.scale = {o.scale / 2, o.scale / 2, o.scale / 2};
            if (k % 3 == 1) file.point_format = 2;
            if (k % 3 == 2) file.point_format = 7, file.version_minor = 4;
        }
        std::string number = std::to_string(k);
        number.insert(0, width - number.size(), '0');
        const std::uint64_t first = o.points * k / o.split, end = o.points * (k + 1) / o.split;
        write_points(o, scene, file, first, end - first, stem + "-" + number + ext);
    }
}
} // namespace

int main(int argc, char** argv) {
    CLI::App app{"lasgen: synthetic LAS scenes (sphere, box, torus, or a ship's deck) for lasmesh"};
    Options o;
    app.add_option("--scene", o.scene, "sphere, box, torus or deck")->capture_default_str();
    app.add_option("--order", o.order,
                   "random: points in no order; scan: in acquisition-like order (consecutive points close together)")
        ->capture_default_str()
        ->check(CLI::IsMember({"random", "scan"}));
    app.add_option("-n,--points", o.points, "Number of points")->capture_default_str();
    app.add_option("--seed", o.seed, "Random seed; the same seed gives the same file")->capture_default_str();
    app.add_option("--las-version", o.version, "LAS version 1.0 to 1.4")->capture_default_str();
    app.add_option("--format", o.format, "Point data record format 0 to 10")->capture_default_str();
    app.add_option("--extra-bytes", o.extra_bytes, "Zero bytes appended to every record")->capture_default_str();
    app.add_option("--color-depth", o.color_depth, "8: 0-255 stored in the 16-bit fields; 16: full range")
        ->capture_default_str();
    app.add_option("--noise", o.noise, "Gaussian noise in metres (default: 0.01 for the deck, 0 for shapes)");
    app.add_option("--size", o.size, "Shape diameter or edge in metres")->capture_default_str();
    app.add_option("--scale", o.scale, "LAS scale factor (coordinate step) in metres")->capture_default_str();
    app.add_option("--epsg", o.epsg, "Declare this EPSG CRS in GeoTIFF keys (4000-4999: geographic), e.g. 32631");
    app.add_option("--origin", o.origin, "X,Y,Z added to the scene (deck default: 431250,6700200,10)")
        ->expected(3)
        ->delimiter(',');
    app.add_option("--color", o.color, "R,G,B of a single shape, 0-255")
        ->expected(3)
        ->delimiter(',')
        ->check(CLI::Range(0, 255));
    app.add_option("-o,--output", o.output, "Output file, or - for standard output")->capture_default_str();
    app.add_option("--split", o.split,
                   "Write the points into N files NAME-0.las ... (a survey of several files), together "
                   "exactly the points of the single file")
        ->check(CLI::Range(1, 100000));
    app.add_option("--split-xy", o.split_xy,
                   "Write the points into N x N files NAME-X_Y.las by where they lie in x and y (map tiles), "
                   "each with its own points' bounds")
        ->check(CLI::Range(1, 64));
    app.add_flag("--split-vary", o.split_vary,
                 "Each file of --split its own offset (whole metres apart), odd files half the scale, every "
                 "third file in point format 2 or 7");
    app.add_option("--measure", o.measure,
                   "Measure this mesh (.ply, .drc, .glb) against the scene's true surfaces, part by part, "
                   "instead of writing points (give the scene options the points were made with)");
    app.add_option("--within", o.within,
                   "With --measure: only the true surfaces inside this world box (a mesh made with lasmesh --bounds)")
        ->expected(6)
        ->delimiter(',');
    app.add_option("--json", o.json, "With --measure: also write the measurement as JSON to this file");
    app.add_option("--samples", o.samples,
                   "With --measure: points spread over the mesh and over the true surfaces, each (fewer: faster, "
                   "coarser figures)")
        ->capture_default_str()
        ->check(CLI::Range(std::size_t{1000}, std::size_t{100'000'000}));
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 1;
    }
    try {
        generate(o);
    } catch (const std::exception& e) {
        std::cerr << "lasgen: " << e.what() << '\n';
        if (o.measure.empty() && o.output != "-") std::remove(o.output.c_str());
        return 2;
    }
    return 0;
}
