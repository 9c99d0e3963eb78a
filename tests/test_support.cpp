// SPDX-License-Identifier: Apache-2.0
// Test helpers: temp folders, file I/O and LAS fixtures from the project's own generator.
#include "test_support.hpp"

#include "lasmesh/error.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unistd.h>
#include <unordered_map>

namespace test {

std::string error_text(const std::function<void()>& call) {
    try {
        call();
    } catch (const lasmesh::Error& e) {
        return e.what();
    }
    FAIL("no error");
    return "";
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TempDir::TempDir() {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("lasmesh-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
}

std::string glb_json(const std::string& glb) {
    std::uint32_t json_length;
    std::memcpy(&json_length, glb.data() + 12, 4);
    return glb.substr(20, json_length);
}

Bytes read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Bytes bytes(text.size());
    std::memcpy(bytes.data(), text.data(), text.size());
    return bytes;
}

void write_file(const std::string& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + path);
}

Bytes make_las(const lasgen::LasLayout& layout, const lasgen::Scene& scene, std::uint64_t count, std::uint64_t seed) {
    lasgen::LasLayout l = layout;
    for (int a = 0; a < 3; ++a) l.offset[a] = std::floor(scene.min[a]);
    Bytes file = lasgen::las_file_head(l, count, scene.min, scene.max, "test scene");
    const std::size_t length = lasgen::record_length(l);
    const std::size_t head = file.size();
    file.resize(head + count * length);
    for (std::uint64_t i = 0; i < count; ++i)
        lasgen::encode_record(l, lasgen::generate_point(scene, seed, i), i, file.data() + head + i * length);
    return file;
}

Bytes make_las_part(const lasgen::LasLayout& layout, const lasgen::Scene& scene, std::uint64_t first,
                    std::uint64_t count, std::uint64_t seed) {
    Bytes file = lasgen::las_file_head(layout, count, scene.min, scene.max, "test scene part");
    const std::size_t length = lasgen::record_length(layout);
    const std::size_t head = file.size();
    file.resize(head + count * length);
    for (std::uint64_t i = 0; i < count; ++i)
        lasgen::encode_record(layout, lasgen::generate_point(scene, seed, first + i), first + i,
                              file.data() + head + i * length);
    return file;
}

std::filesystem::path shared_las_folder() {
    // shared/ sits beside the checkout (CI clones main next to it); LASMESH_SHARED overrides.
    const char* override_dir = std::getenv("LASMESH_SHARED");
    std::filesystem::path shared = override_dir ? std::filesystem::path(override_dir)
                                                : std::filesystem::path(LASMESH_SOURCE_DIR).parent_path() / "shared";
    std::filesystem::path folder = shared / "data" / "las";
    return std::filesystem::exists(folder / "MANIFEST.tsv") ? folder : std::filesystem::path();
}

} // namespace test

namespace test {

DenseGrid dense(const lasmesh::CellGrid& grid) {
    DenseGrid d;
    d.grid = &grid;
    const std::uint64_t cells = grid.spec.cell_count();
    d.count.assign(cells, 0);
    if (grid.has_color()) d.red = d.green = d.blue = d.count;
    grid.for_each_cell([&](const std::array<std::int64_t, 3>& c, std::uint64_t r) {
        // Bricks may reach beyond the grid, but no point falls there.
        REQUIRE(c[0] < std::int64_t{grid.spec.dims[0]});
        REQUIRE(c[1] < std::int64_t{grid.spec.dims[1]});
        REQUIRE(c[2] < std::int64_t{grid.spec.dims[2]});
        REQUIRE(grid.cells[r].count > 0); // only occupied cells are kept
        const std::uint64_t index = (c[2] * grid.spec.dims[1] + c[1]) * grid.spec.dims[0] + c[0];
        d.count[index] = grid.cells[r].count;
        if (grid.has_color())
            d.red[index] = grid.cells[r].color[0], d.green[index] = grid.cells[r].color[1],
            d.blue[index] = grid.cells[r].color[2];
    });
    return d;
}

lasmesh::Rgb8 DenseGrid::mean_color(std::uint64_t cell) const {
    lasmesh::CellSums sums;
    sums.count = count[cell];
    if (!red.empty()) sums.color = {red[cell], green[cell], blue[cell]};
    return grid->mean_color(sums);
}

lasmesh::CellGrid grid_from_counts(const lasmesh::GridSpec& spec, const std::vector<std::uint64_t>& count,
                                   const std::vector<std::uint64_t>& red, const std::vector<std::uint64_t>& green,
                                   const std::vector<std::uint64_t>& blue, std::uint32_t color_max_word) {
    using lasmesh::CellGrid;
    CellGrid g;
    g.spec = spec;
    g.color = !red.empty();
    g.color_max_word = color_max_word;
    // Raw units of a thousandth of a cell, so a cell's centre is 500 raw units from its start.
    for (int a = 0; a < 3; ++a) {
        g.scale[a] = spec.cell_size / 1000;
        g.offset[a] = spec.origin[a];
        g.axes[a] = lasmesh::axis_cells(spec, a, g.scale[a], g.offset[a]);
        g.bricks[a] = static_cast<std::uint32_t>((spec.dims[a] + CellGrid::brick_size - 1) / CellGrid::brick_size);
    }
    // Brick by brick in ascending order, each brick's occupied cells in the order of their bits.
    for (std::uint64_t key = 0; key < std::uint64_t{g.bricks[0]} * g.bricks[1] * g.bricks[2]; ++key) {
        std::array<lasmesh::CellSums, CellGrid::brick_cells> brick{};
        for (unsigned bit = 0; bit < CellGrid::brick_cells; ++bit) {
            const auto c = g.cell_in_brick(key, bit);
            if (c[0] >= std::int64_t{spec.dims[0]} || c[1] >= std::int64_t{spec.dims[1]} ||
                c[2] >= std::int64_t{spec.dims[2]})
                continue;
            const std::uint64_t index =
                (std::uint64_t(c[2]) * spec.dims[1] + std::uint64_t(c[1])) * spec.dims[0] + std::uint64_t(c[0]);
            lasmesh::CellSums& cell = brick[bit];
            cell.count = count[index];
            for (int a = 0; a < 3; ++a) // every point at the cell's centre
                cell.position[a] = count[index] * static_cast<std::uint64_t>((g.axes[a].starts[std::size_t(c[a]) + 1] -
                                                                              g.axes[a].starts[std::size_t(c[a])]) /
                                                                             2);
            if (g.color) cell.color = {red[index], green[index], blue[index]};
            g.points_read += count[index];
        }
        const std::uint64_t first = g.cells.size();
        const std::uint64_t mask = g.append_occupied(brick);
        if (mask == 0) continue;
        g.brick_keys.push_back(key);
        g.brick_masks.push_back(mask);
        g.brick_first.push_back(first);
    }
    g.index_bricks();
    return g;
}

lasmesh::ComputeDevice& device() {
    static lasmesh::ComputeDevice shared("auto"); // one context for the whole test run
    return shared;
}

// A LAS 1.2 format-3 file (format 1 without colour) holding exactly `points`.
Bytes las_with_points(const std::vector<lasgen::GeneratedPoint>& points, const lasmesh::Vec3& min,
                      const lasmesh::Vec3& max, int color_bits, int format, double scale) {
    lasgen::LasLayout layout;
    layout.point_format = format;
    layout.color_bits = color_bits;
    layout.scale = {scale, scale, scale};
    Bytes file = lasgen::las_file_head(layout, points.size(), min, max, "fixture");
    const std::size_t head = file.size(), length = lasgen::record_length(layout);
    file.resize(head + points.size() * length);
    for (std::size_t i = 0; i < points.size(); ++i)
        lasgen::encode_record(layout, points[i], i, file.data() + head + i * length);
    return file;
}

lasmesh::CellGrid accumulate_file(const std::string& path, lasmesh::AccumulateOptions options) {
    lasmesh::LasReader reader(path);
    return lasmesh::accumulate_cells(reader, device(), options);
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::string part;
    std::istringstream in(text);
    while (std::getline(in, part, separator)) parts.push_back(part);
    if (!text.empty() && text.back() == separator) parts.emplace_back();
    return parts;
}

std::vector<Row> read_manifest(const std::filesystem::path& folder) {
    std::ifstream in(folder / "MANIFEST.tsv");
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> columns = split(line, '\t');
    std::vector<Row> rows;
    while (std::getline(in, line)) {
        const std::vector<std::string> cells = split(line, '\t');
        Row row;
        for (std::size_t i = 0; i < columns.size() && i < cells.size(); ++i) row[columns[i]] = cells[i];
        rows.push_back(row);
    }
    return rows;
}

} // namespace test

namespace test {

namespace {

using lasmesh::Vec3;

Vec3 minus(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot3(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Vec3 corner(const lasmesh::Mesh& m, std::uint32_t v) {
    return {m.positions[v][0], m.positions[v][1], m.positions[v][2]};
}

// The distance from p to triangle abc: the closest point by the regions of the triangle's
// Voronoi diagram (Ericson, "Real-Time Collision Detection", 5.1.5).
double triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = minus(b, a), ac = minus(c, a), ap = minus(p, a);
    const auto at = [&](double v, double w) {
        const Vec3 q{a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w};
        const Vec3 d = minus(p, q);
        return std::sqrt(dot3(d, d));
    };
    const double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) return at(0, 0);
    const Vec3 bp = minus(p, b);
    const double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) return at(1, 0);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return at(d1 / (d1 - d3), 0);
    const Vec3 cp = minus(p, c);
    const double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) return at(0, 1);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return at(0, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return at(1 - w, w);
    }
    const double denominator = 1 / (va + vb + vc);
    return at(vb * denominator, vc * denominator);
}

} // namespace

std::vector<Vec3> dense_samples(const lasmesh::Mesh& mesh, double spacing) {
    std::vector<Vec3> points;
    for (const auto& t : mesh.triangles) {
        const Vec3 a = corner(mesh, t[0]), b = corner(mesh, t[1]), c = corner(mesh, t[2]);
        double longest = 0;
        for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
            longest = std::max(longest, std::sqrt(dot3(minus(p, q), minus(p, q))));
        const int n = std::clamp(static_cast<int>(std::ceil(longest / spacing)), 1, 12);
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const double v = double(i) / n, w = double(j) / n;
                points.push_back({a[0] + (b[0] - a[0]) * v + (c[0] - a[0]) * w,
                                  a[1] + (b[1] - a[1]) * v + (c[1] - a[1]) * w,
                                  a[2] + (b[2] - a[2]) * v + (c[2] - a[2]) * w});
            }
    }
    return points;
}

double farthest_from(const lasmesh::Mesh& surface, const std::vector<Vec3>& points, double window) {
    // Cells no smaller than the mean edge, so a triangle is filed in few of them.
    const double reach = window;
    double edges = 0;
    for (const auto& t : surface.triangles)
        edges += std::sqrt(dot3(minus(corner(surface, t[0]), corner(surface, t[1])),
                                minus(corner(surface, t[0]), corner(surface, t[1]))));
    window = std::max(window, edges / std::max<std::size_t>(1, surface.triangles.size()));
    // Triangles filed by the cells (of edge `window`) their box, grown by `window`, meets.
    struct Hash {
        std::size_t operator()(const std::array<std::int64_t, 3>& c) const {
            return std::size_t((c[0] * 73856093) ^ (c[1] * 19349663) ^ (c[2] * 83492791));
        }
    };
    std::unordered_map<std::array<std::int64_t, 3>, std::vector<std::uint32_t>, Hash> cells;
    const auto cell_of = [&](double x) { return static_cast<std::int64_t>(std::floor(x / window)); };
    for (std::uint32_t f = 0; f < surface.triangles.size(); ++f) {
        std::array<std::int64_t, 3> lo{}, hi{};
        for (int a = 0; a < 3; ++a) {
            double low = 1e300, high = -1e300;
            for (const std::uint32_t v : surface.triangles[f])
                low = std::min(low, double(surface.positions[v][a])),
                high = std::max(high, double(surface.positions[v][a]));
            lo[a] = cell_of(low - window), hi[a] = cell_of(high + window);
        }
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
            for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
                for (std::int64_t x = lo[0]; x <= hi[0]; ++x) cells[{x, y, z}].push_back(f);
    }
    // A point nearer than the farthest so far cannot change the answer, so its search stops at the
    // first triangle that near (Taha & Hanbury 2015, an exact Hausdorff distance with early
    // breaks), and the triangle nearest the previous point, usually near this one too (samples
    // come triangle by triangle), is tried first: the same result in a fraction of the work.
    double farthest = 0;
    std::uint32_t last = std::numeric_limits<std::uint32_t>::max();
    const auto distance_to = [&](const Vec3& p, std::uint32_t f) {
        const auto& t = surface.triangles[f];
        return triangle_distance(p, corner(surface, t[0]), corner(surface, t[1]), corner(surface, t[2]));
    };
    for (const Vec3& p : points) {
        const auto found = cells.find({cell_of(p[0]), cell_of(p[1]), cell_of(p[2])});
        double nearest = std::numeric_limits<double>::infinity();
        if (found != cells.end()) {
            std::uint32_t nearest_face = last;
            if (last < surface.triangles.size()) nearest = distance_to(p, last);
            if (nearest > farthest)
                for (const std::uint32_t f : found->second) {
                    if (const double d = distance_to(p, f); d < nearest) nearest = d, nearest_face = f;
                    if (nearest <= farthest) break;
                }
            last = nearest_face;
        }
        farthest = std::max(farthest, nearest > reach ? std::numeric_limits<double>::infinity() : nearest);
    }
    return farthest;
}

} // namespace test
