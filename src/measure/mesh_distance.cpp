// SPDX-License-Identifier: Apache-2.0
// Nearest-neighbour search by branch and bound over a bounding volume hierarchy.
#include "measure/mesh_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace lasmesh {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

Vec3 sub(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 to_vec(const Point3f& p) {
    return {p[0], p[1], p[2]};
}

double point_segment_squared(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = sub(b, a), ap = sub(p, a);
    const double length_sq = dot(ab, ab);
    const double t = length_sq > 0 ? std::clamp(dot(ap, ab) / length_sq, 0.0, 1.0) : 0.0;
    const Vec3 d = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
    return dot(d, d);
}

using Box = std::pair<Point3f, Point3f>;

Box merge(const Box& a, const Box& b) {
    Box m;
    for (int k = 0; k < 3; ++k)
        m.first[k] = std::min(a.first[k], b.first[k]), m.second[k] = std::max(a.second[k], b.second[k]);
    return m;
}

// Builds the tree top-down. Ties in the median split are broken by item id, so the tree (and
// with it the order of work, though never the result) is the same on every run.
Bvh build_bvh(const std::vector<Box>& boxes) {
    constexpr std::uint32_t leaf_size = 4;
    Bvh t;
    t.items.resize(boxes.size());
    std::iota(t.items.begin(), t.items.end(), 0u);
    if (boxes.empty()) return t;
    auto centre = [&](std::uint32_t i, int k) { return boxes[i].first[k] + boxes[i].second[k]; };
    struct Job {
        std::uint32_t node, begin, end;
    };
    std::vector<Job> jobs{{0, 0, static_cast<std::uint32_t>(boxes.size())}};
    t.nodes.resize(1);
    while (!jobs.empty()) {
        const Job job = jobs.back();
        jobs.pop_back();
        Box box = boxes[t.items[job.begin]];
        for (std::uint32_t i = job.begin + 1; i < job.end; ++i) box = merge(box, boxes[t.items[i]]);
        Bvh::Node& node = t.nodes[job.node];
        node.lo = box.first, node.hi = box.second;
        if (job.end - job.begin <= leaf_size) {
            node.first = job.begin, node.count = job.end - job.begin;
            continue;
        }
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (box.second[k] - box.first[k] > box.second[axis] - box.first[axis]) axis = k;
        const std::uint32_t middle = job.begin + (job.end - job.begin) / 2;
        std::nth_element(t.items.begin() + job.begin, t.items.begin() + middle, t.items.begin() + job.end,
                         [&](std::uint32_t a, std::uint32_t b) {
                             const float ca = centre(a, axis), cb = centre(b, axis);
                             return ca < cb || (ca == cb && a < b);
                         });
        const auto left = static_cast<std::uint32_t>(t.nodes.size());
        node.first = left, node.count = 0; // `node` is not used after the resize below
        t.nodes.resize(t.nodes.size() + 2);
        jobs.push_back({left, job.begin, middle});
        jobs.push_back({left + 1, middle, job.end});
    }
    return t;
}

double box_distance_squared(const Bvh::Node& n, const Vec3& p) {
    double d = 0;
    for (int k = 0; k < 3; ++k) {
        const double below = n.lo[k] - p[k], above = p[k] - n.hi[k];
        const double out = std::max({below, above, 0.0});
        d += out * out;
    }
    return d;
}

// The smallest squared distance `item_distance_sq` gives over the tree's items, visiting the
// nearer child first and skipping every box farther than the best distance so far. `hint`, when
// given, names an item likely to be near (the previous query's answer, for queries in scan
// order): starting from its distance prunes most boxes at once. It is updated to the nearest
// item. The distance found does not depend on the hint.
template <class ItemDistance>
double nearest_squared(const Bvh& t, const Vec3& p, ItemDistance item_distance_sq, std::uint32_t* hint) {
    if (t.nodes.empty()) return infinity;
    double best = infinity;
    std::uint32_t best_item = 0;
    if (hint && *hint < t.items.size()) best = item_distance_sq(*hint), best_item = *hint;
    std::pair<std::uint32_t, double> stack[64];
    int depth = 0;
    stack[depth++] = {0, box_distance_squared(t.nodes[0], p)};
    while (depth > 0) {
        const auto [index, box_distance] = stack[--depth];
        if (box_distance >= best) continue;
        const Bvh::Node& n = t.nodes[index];
        if (n.count > 0) {
            for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
                const double d = item_distance_sq(t.items[i]);
                if (d < best) best = d, best_item = t.items[i];
            }
            continue;
        }
        double near = box_distance_squared(t.nodes[n.first], p), far = box_distance_squared(t.nodes[n.first + 1], p);
        std::uint32_t near_index = n.first, far_index = n.first + 1;
        if (far < near) std::swap(near, far), std::swap(near_index, far_index);
        stack[depth++] = {far_index, far};
        stack[depth++] = {near_index, near};
    }
    if (hint) *hint = best_item;
    return best;
}

} // namespace

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Inside the prism over the triangle the distance is to the plane; outside it, to the
    // nearest edge.
    const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    const Vec3 n = cross(ab, ac);
    const double n_sq = dot(n, n);
    if (n_sq > 0) {
        // Barycentric coordinates of p's projection: ap = u ab + v ac + t n.
        const double v = dot(cross(ab, ap), n) / n_sq, u = dot(cross(ap, ac), n) / n_sq;
        if (u >= 0 && v >= 0 && u + v <= 1) return std::abs(dot(ap, n)) / std::sqrt(n_sq);
    }
    return std::sqrt(
        std::min({point_segment_squared(p, a, b), point_segment_squared(p, b, c), point_segment_squared(p, c, a)}));
}

TriangleSearch::TriangleSearch(const Mesh& mesh) : mesh_(mesh) {
    std::vector<Box> boxes(mesh.triangles.size());
    for (std::size_t t = 0; t < boxes.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        boxes[t] = {mesh.positions[tri[0]], mesh.positions[tri[0]]};
        for (int c = 1; c < 3; ++c) boxes[t] = merge(boxes[t], {mesh.positions[tri[c]], mesh.positions[tri[c]]});
    }
    tree_ = build_bvh(boxes);
}

double TriangleSearch::distance(const Vec3& p, std::uint32_t* hint) const {
    const auto& P = mesh_.positions;
    return std::sqrt(nearest_squared(
        tree_, p,
        [&](std::uint32_t t) {
            const auto& tri = mesh_.triangles[t];
            const double d = point_triangle_distance(p, to_vec(P[tri[0]]), to_vec(P[tri[1]]), to_vec(P[tri[2]]));
            return d * d;
        },
        hint));
}

PointSearch::PointSearch(std::vector<Point3f> points) : points_(std::move(points)) {
    std::vector<Box> boxes(points_.size());
    for (std::size_t i = 0; i < boxes.size(); ++i) boxes[i] = {points_[i], points_[i]};
    tree_ = build_bvh(boxes);
}

double PointSearch::distance(const Vec3& p, std::uint32_t* hint) const {
    return std::sqrt(nearest_squared(
        tree_, p,
        [&](std::uint32_t i) {
            const Vec3 d = sub(p, to_vec(points_[i]));
            return dot(d, d);
        },
        hint));
}

std::vector<Vec3> sample_surface(const Mesh& mesh, std::size_t count) {
    std::vector<double> cumulative(mesh.triangles.size());
    double total = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        const Vec3 a = to_vec(mesh.positions[tri[0]]);
        const Vec3 n = cross(sub(to_vec(mesh.positions[tri[1]]), a), sub(to_vec(mesh.positions[tri[2]]), a));
        cumulative[t] = total += 0.5 * std::sqrt(dot(n, n));
    }
    std::vector<Vec3> samples;
    if (total <= 0 || count == 0) return samples;
    samples.reserve(count);
    auto unit = [](std::uint64_t x) { // splitmix64, to a double in [0, 1)
        x += 0x9E3779B97F4A7C15ull;
        x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
        x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
        return static_cast<double>((x ^ (x >> 31)) >> 11) * 0x1p-53;
    };
    for (std::size_t s = 0; s < count; ++s) {
        const double at = (s + unit(2 * s)) / count * total;
        const std::size_t t = std::min<std::size_t>(
            std::upper_bound(cumulative.begin(), cumulative.end(), at) - cumulative.begin(), cumulative.size() - 1);
        const auto& tri = mesh.triangles[t];
        double u = unit(2 * s + 1), v = unit(~s);
        if (u + v > 1) u = 1 - u, v = 1 - v; // fold the parallelogram onto the triangle
        const Vec3 a = to_vec(mesh.positions[tri[0]]), b = to_vec(mesh.positions[tri[1]]),
                   c = to_vec(mesh.positions[tri[2]]);
        samples.push_back({a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0]), a[1] + u * (b[1] - a[1]) + v * (c[1] - a[1]),
                           a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2])});
    }
    return samples;
}

} // namespace lasmesh
