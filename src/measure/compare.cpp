// SPDX-License-Identifier: Apache-2.0
// compare: stream the cloud, keep an even subset, then measure both ways in parallel. Each
// distance lands in its own slot, so the statistics do not depend on the thread count.
#include "lasmesh/compare.hpp"

#include "lasmesh/error.hpp"
#include "measure/mesh_distance.hpp"
#include "read/crs.hpp"
#include "read/crs_transform.hpp"
#include "read/input_stream.hpp"
#include "read/las_point.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace lasmesh {

namespace {

// Loads point i of n when it is the first of its stride: keeps `wanted` of n, evenly spread.
bool selected(std::uint64_t i, std::uint64_t n, std::uint64_t wanted) {
    if (wanted >= n) return true;
    return (static_cast<unsigned __int128>(i + 1) * wanted) / n != (static_cast<unsigned __int128>(i) * wanted) / n;
}

std::vector<Point3f> load_points(LasReader& cloud, const Vec3& origin, std::uint64_t wanted, std::uint64_t& read,
                                 const CrsTransform* transform) {
    const PointDecoder decoder(cloud.header());
    const std::uint64_t n = cloud.header().point_count;
    std::vector<Point3f> points;
    // Not reserved from the header's count: a damaged header may promise far more than the file
    // holds. Chunks are bounded in bytes, whatever the record length.
    std::vector<std::byte> chunk(std::max<std::size_t>(1, (std::size_t{16} << 20) / decoder.record_length) *
                                 decoder.record_length);
    std::vector<double> x, y, z;
    while (std::size_t count = cloud.read_records(chunk)) {
        x.clear(), y.clear(), z.clear();
        for (std::size_t r = 0; r < count; ++r, ++read) {
            if (!selected(read, n, wanted)) continue;
            const Vec3 w = decoder.position(chunk.data() + r * decoder.record_length);
            x.push_back(w[0]), y.push_back(w[1]), z.push_back(w[2]);
        }
        if (transform && transform->apply(x.data(), y.data(), z.data(), x.size()) != x.size())
            throw_input_error(cloud.stream().name(), "a point near record " + std::to_string(read) +
                                                         " lies outside the area of its coordinate system: it "
                                                         "cannot be brought into the mesh's");
        for (std::size_t i = 0; i < x.size(); ++i)
            points.push_back({static_cast<float>(x[i] - origin[0]), static_cast<float>(y[i] - origin[1]),
                              static_cast<float>(z[i] - origin[2])});
    }
    return points;
}

// The points' indices in Morton (Z-curve) order of their positions: queries in this order follow
// each other in space, so each starts from a tight bound (the previous answer) and warm caches.
// Only the speed depends on it: every distance lands in its own point's slot.
std::vector<std::uint32_t> spatial_order(const PointSearch& points) {
    const std::size_t n = points.size();
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
            lo[a] = std::min(lo[a], points.point(i)[a]), hi[a] = std::max(hi[a], points.point(i)[a]);
    auto spread = [](std::uint64_t x) { // 21 bits to every third bit of 63
        x &= 0x1FFFFF;
        x = (x | x << 32) & 0x1F00000000FFFFull;
        x = (x | x << 16) & 0x1F0000FF0000FFull;
        x = (x | x << 8) & 0x100F00F00F00F00Full;
        x = (x | x << 4) & 0x10C30C30C30C30C3ull;
        x = (x | x << 2) & 0x1249249249249249ull;
        return x;
    };
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        std::uint64_t key = 0;
        for (int a = 0; a < 3; ++a) {
            const double extent = hi[a] - lo[a];
            const double unit = extent > 0 ? (points.point(i)[a] - lo[a]) / extent : 0;
            key |= spread(static_cast<std::uint64_t>(unit * 0x1FFFFF)) << a;
        }
        keyed[i] = {key, static_cast<std::uint32_t>(i)};
    });
    tbb::parallel_sort(keyed.begin(), keyed.end()); // pairs are distinct: the order is unique
    std::vector<std::uint32_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = keyed[k].second;
    return order;
}

} // namespace

DistanceStats summarize(std::vector<double>& d, double cell_size) {
    DistanceStats s;
    s.count = d.size();
    if (d.empty()) return s;
    std::sort(d.begin(), d.end());
    long double sum = 0, sum_sq = 0;
    for (double v : d) sum += v, sum_sq += static_cast<long double>(v) * v;
    const double n = static_cast<double>(d.size());
    s.mean = static_cast<double>(sum / n);
    s.std = std::sqrt(std::max(0.0, static_cast<double>(sum_sq / n) - s.mean * s.mean));
    auto rank = [&](double q) {
        return d[std::min(d.size() - 1, static_cast<std::size_t>(std::ceil(q * n)) - (q > 0))];
    };
    s.median = rank(0.5), s.p95 = rank(0.95), s.p99 = rank(0.99), s.max = d.back();
    if (cell_size > 0) {
        auto share = [&](double limit) { return (std::upper_bound(d.begin(), d.end(), limit) - d.begin()) / n; };
        s.within_1_cell = share(cell_size), s.within_2_cells = share(2 * cell_size);
        const auto near_end = std::upper_bound(d.begin(), d.end(), 2 * cell_size);
        long double near_sum = 0;
        for (auto v = d.begin(); v != near_end; ++v) near_sum += *v;
        if (near_end != d.begin())
            s.mean_within_2_cells = static_cast<double>(near_sum / static_cast<long double>(near_end - d.begin()));
    }
    return s;
}

namespace {
// Zero when every triangle is degenerate: then no distance to "the surface" means anything.
bool has_area(const Mesh& mesh) {
    for (const auto& t : mesh.triangles) {
        const auto& a = mesh.positions[t[0]];
        const auto& b = mesh.positions[t[1]];
        const auto& c = mesh.positions[t[2]];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        if (u[1] * v[2] - u[2] * v[1] != 0 || u[2] * v[0] - u[0] * v[2] != 0 || u[0] * v[1] - u[1] * v[0] != 0)
            return true;
    }
    return false;
}
} // namespace

CompareResult compare(const Mesh& mesh, LasReader& cloud, const CompareOptions& options) {
    // Statistics over nothing would print as numbers with exit 0: refuse instead.
    if (mesh.triangles.empty()) throw Error(ErrorKind::input, "the mesh has no triangles: nothing to measure");
    if (!has_area(mesh))
        throw Error(ErrorKind::input, "every triangle of the mesh has zero area: there is no surface to measure");
    CompareResult result;
    result.cell_size = options.cell_size > 0 ? options.cell_size : mesh.cell_size;
    const auto step = [&](const std::string& what) {
        if (options.on_step) options.on_step(what);
    };
    // A cloud in another CRS than the mesh records (a mesh of a file in degrees is in UTM):
    // brought into the mesh's, so that distances are lengths in one unit.
    std::unique_ptr<CrsTransform> transform;
    if (const std::optional<CrsInfo> cloud_crs = read_crs(cloud.header()); cloud_crs && !mesh.crs.empty()) {
        std::optional<CrsInfo> mesh_crs;
        try {
            mesh_crs = crs_from_text(mesh.crs);
        } catch (const Error&) {
            // Not a CRS PROJ knows: measured as they are (the command line warns).
        }
        if (mesh_crs && cloud_crs->identified() && crs_for_outputs(*cloud_crs) != crs_for_outputs(*mesh_crs)) {
            transform = std::make_unique<CrsTransform>(*cloud_crs, *mesh_crs, cloud.stream().name());
            result.cloud_transformed = crs_summary(*cloud_crs) + " to " + crs_summary(*mesh_crs);
        }
    }
    step("reading the cloud");
    const PointSearch points(load_points(cloud, mesh.origin, std::max<std::uint64_t>(options.samples, 1),
                                         result.points_read, transform.get()));
    result.points_used = points.size();
    if (points.size() == 0)
        throw_input_error(cloud.stream().name(), "has no point records: nothing to measure against");

    step("measuring cloud to mesh (" + std::to_string(points.size()) + " points)");
    std::vector<double> to_mesh(points.size());
    const TriangleSearch triangles(mesh);
    const std::vector<std::uint32_t> order = spatial_order(points);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4096), [&](const auto& range) {
        std::uint32_t hint = std::numeric_limits<std::uint32_t>::max();
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
            const std::uint32_t i = order[k];
            to_mesh[i] = triangles.distance(points.point(i), &hint);
        }
    });
    result.cloud_to_mesh = summarize(to_mesh, result.cell_size);

    step("measuring mesh to cloud");
    const std::vector<Vec3> samples = sample_surface(mesh, options.mesh_samples);
    result.samples_used = samples.size();
    std::vector<double> to_cloud(samples.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size(), 4096), [&](const auto& range) {
        std::uint32_t hint = std::numeric_limits<std::uint32_t>::max(); // samples come triangle by triangle
        for (std::size_t i = range.begin(); i != range.end(); ++i) to_cloud[i] = points.distance(samples[i], &hint);
    });
    result.mesh_to_cloud = summarize(to_cloud, result.cell_size);

    result.vertex_distance.resize(mesh.positions.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.positions.size(), 4096), [&](const auto& range) {
        std::uint32_t hint = std::numeric_limits<std::uint32_t>::max(); // vertices come in lattice order
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            const auto& p = mesh.positions[v];
            result.vertex_distance[v] = points.distance({p[0], p[1], p[2]}, &hint);
        }
    });
    return result;
}

std::array<std::uint8_t, 3> heat_color(double distance, double scale) {
    static const double stops[5][3] = {{0, 0, 255}, {0, 255, 255}, {0, 255, 0}, {255, 255, 0}, {255, 0, 0}};
    const double t = scale > 0 ? std::clamp(distance / scale, 0.0, 1.0) * 4 : 4;
    const int i = std::min(static_cast<int>(t), 3);
    const double f = t - i;
    std::array<std::uint8_t, 3> c;
    for (int k = 0; k < 3; ++k)
        c[k] = static_cast<std::uint8_t>(std::lround(stops[i][k] + f * (stops[i + 1][k] - stops[i][k])));
    return c;
}

} // namespace lasmesh
