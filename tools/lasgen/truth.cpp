// SPDX-License-Identifier: Apache-2.0
// Both directions of the error against an analytic truth, as in the study's section 5 but with
// the true surfaces in place of the cloud: mesh to truth (where the mesh invents or fattens
// shapes) and truth to mesh (what it misses), each attributed to the part it concerns.
#include "truth.hpp"

#include "measure/mesh_distance.hpp"

#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace lasgen {

namespace {

double dot_product(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 minus(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec3 cross_product(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = minus(b, a), ap = minus(p, a);
    const double len2 = dot_product(ab, ab);
    const double t = len2 > 0 ? std::clamp(dot_product(ap, ab) / len2, 0.0, 1.0) : 0.0;
    const Vec3 d{ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
    return std::sqrt(dot_product(d, d));
}

double quad_distance(const Primitive& p, const Vec3& q) {
    // Coordinates of q's projection in the (u, v) frame from the 2 x 2 Gram system; inside the
    // parallelogram the distance is to its plane, outside to the nearest of its four edges.
    const Vec3 d = minus(q, p.origin);
    const double uu = dot_product(p.u, p.u), uv = dot_product(p.u, p.v), vv = dot_product(p.v, p.v),
                 du = dot_product(d, p.u), dv = dot_product(d, p.v);
    const double det = uu * vv - uv * uv;
    const double s = (du * vv - dv * uv) / det, t = (dv * uu - du * uv) / det;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) {
        const Vec3 n = cross_product(p.u, p.v);
        return std::abs(dot_product(d, n)) / std::sqrt(dot_product(n, n));
    }
    const Vec3 a = p.origin, b{a[0] + p.u[0], a[1] + p.u[1], a[2] + p.u[2]},
               c{b[0] + p.v[0], b[1] + p.v[1], b[2] + p.v[2]}, e{a[0] + p.v[0], a[1] + p.v[1], a[2] + p.v[2]};
    return std::min(
        {segment_distance(q, a, b), segment_distance(q, b, c), segment_distance(q, c, e), segment_distance(q, e, a)});
}

double cylinder_distance(const Primitive& p, const Vec3& q) {
    const double length = std::sqrt(dot_product(p.u, p.u));
    const Vec3 d = minus(q, p.origin);
    const double h = dot_product(d, p.u) / length;
    const double radial2 = std::max(0.0, dot_product(d, d) - h * h);
    const double off = std::sqrt(radial2) - p.radius;
    if (h >= 0 && h <= length) return std::abs(off);
    const double beyond = h < 0 ? -h : h - length; // past an end: to the end's circle
    return std::sqrt(beyond * beyond + off * off);
}

struct Stats {
    double mean = 0, median = 0, p95 = 0, p99 = 0, max = 0;
};

// Nearest-rank statistics; reorders `values`.
Stats stats_of(std::vector<double>& values) {
    Stats s;
    if (values.empty()) return s;
    std::sort(values.begin(), values.end());
    double sum = 0;
    for (double v : values) sum += v;
    auto rank = [&](double q) {
        const std::size_t k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
        return values[std::clamp<std::size_t>(k, 1, values.size()) - 1];
    };
    s.mean = sum / static_cast<double>(values.size());
    s.median = rank(0.5), s.p95 = rank(0.95), s.p99 = rank(0.99), s.max = values.back();
    return s;
}

bool inside(const std::vector<double>& box, const Vec3& w) {
    return w[0] >= box[0] && w[1] >= box[1] && w[2] >= box[2] && w[0] <= box[3] && w[1] <= box[4] && w[2] <= box[5];
}

bool is_surface(const Primitive& p) {
    return p.kind != PrimitiveKind::ball;
}

} // namespace

double distance_to(const Primitive& p, const Vec3& q) {
    const Vec3 d = minus(q, p.origin);
    switch (p.kind) {
    case PrimitiveKind::quad: return quad_distance(p, q);
    case PrimitiveKind::cylinder: return cylinder_distance(p, q);
    case PrimitiveKind::sphere: return std::abs(std::sqrt(dot_product(d, d)) - p.radius);
    case PrimitiveKind::torus: {
        const double ring = std::hypot(d[0], d[1]) - p.radius;
        return std::abs(std::hypot(ring, d[2]) - p.minor_radius);
    }
    case PrimitiveKind::ball: return std::max(0.0, std::sqrt(dot_product(d, d)) - p.radius);
    }
    return std::numeric_limits<double>::infinity();
}

namespace {

// The unit direction from the primitive's surface nearest `q` to its free side.
Vec3 free_side(const Primitive& p, const Vec3& q) {
    auto unit = [](const Vec3& d) {
        const double length = std::sqrt(dot_product(d, d));
        return length > 0 ? Vec3{d[0] / length, d[1] / length, d[2] / length} : Vec3{};
    };
    if (p.two_sided) return {};
    const Vec3 d = minus(q, p.origin);
    switch (p.kind) {
    case PrimitiveKind::quad: return p.outside;
    case PrimitiveKind::cylinder: {
        const Vec3 axis = unit(p.u);
        const double t = dot_product(d, axis);
        return unit({d[0] - t * axis[0], d[1] - t * axis[1], d[2] - t * axis[2]});
    }
    case PrimitiveKind::torus: {
        const double ring = std::hypot(d[0], d[1]);
        if (!(ring > 0)) return {};
        return unit({d[0] - p.radius * d[0] / ring, d[1] - p.radius * d[1] / ring, d[2]});
    }
    case PrimitiveKind::sphere:
    case PrimitiveKind::ball: return unit(d);
    }
    return {};
}

} // namespace

TruthReport measure_against_truth(const Scene& scene, const lasmesh::Mesh& mesh, const TruthOptions& options) {
    TruthReport report;
    std::vector<std::size_t> surfaces, part_of(scene.primitives.size());
    for (std::size_t i = 0; i < scene.primitives.size(); ++i) {
        const Primitive& p = scene.primitives[i];
        if (!is_surface(p)) continue;
        surfaces.push_back(i);
        auto it = std::find_if(report.parts.begin(), report.parts.end(),
                               [&](const PartError& e) { return e.part == p.part; });
        if (it == report.parts.end()) it = report.parts.insert(report.parts.end(), PartError{p.part});
        part_of[i] = static_cast<std::size_t>(it - report.parts.begin());
    }
    const std::size_t part_count = report.parts.size();

    // Mesh to truth: every sample goes to its nearest primitive.
    for (const auto& t : mesh.triangles) {
        const Vec3 a{mesh.positions[t[0]][0], mesh.positions[t[0]][1], mesh.positions[t[0]][2]};
        const Vec3 b{mesh.positions[t[1]][0], mesh.positions[t[1]][1], mesh.positions[t[1]][2]};
        const Vec3 c{mesh.positions[t[2]][0], mesh.positions[t[2]][1], mesh.positions[t[2]][2]};
        const Vec3 n = cross_product(minus(b, a), minus(c, a));
        report.mesh_area += 0.5 * std::sqrt(dot_product(n, n));
    }
    report.triangles = mesh.triangles.size();
    // Each triangle, by its centroid, to its nearest part: where the triangle count goes; and
    // whether it faces its nearest surface's free side (the triangles more than 60 degrees from
    // that surface's plane, edge-on where a sheet ends or turns, left out).
    std::vector<std::size_t> triangle_part(mesh.triangles.size(), part_count);
    std::vector<double> facing_area(mesh.triangles.size(), 0); // its area: + faces the free side, - the solid
    tbb::parallel_for(std::size_t{0}, mesh.triangles.size(), [&](std::size_t t) {
        Vec3 corner[3];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.triangles[t][k];
            corner[k] = to_local(scene, {mesh.origin[0] + mesh.positions[v][0], mesh.origin[1] + mesh.positions[v][1],
                                         mesh.origin[2] + mesh.positions[v][2]});
        }
        const Vec3 q{(corner[0][0] + corner[1][0] + corner[2][0]) / 3, (corner[0][1] + corner[1][1] + corner[2][1]) / 3,
                     (corner[0][2] + corner[1][2] + corner[2][2]) / 3};
        double best = options.floating;
        std::size_t nearest_surface = scene.primitives.size();
        for (std::size_t i : surfaces)
            if (const double d = distance_to(scene.primitives[i], q); d <= best)
                best = d, triangle_part[t] = part_of[i], nearest_surface = i;
        if (nearest_surface == scene.primitives.size()) return;
        const Vec3 normal = cross_product(minus(corner[1], corner[0]), minus(corner[2], corner[0]));
        const Vec3 free = free_side(scene.primitives[nearest_surface], q);
        const double twice_area = std::sqrt(dot_product(normal, normal)), along = dot_product(normal, free);
        if (std::abs(along) >= 0.5 * twice_area) facing_area[t] = along > 0 ? 0.5 * twice_area : -0.5 * twice_area;
    });
    std::vector<double> facing_free(part_count, 0), facing_decided(part_count, 0);
    for (std::size_t t = 0; t < triangle_part.size(); ++t) {
        const std::size_t k = triangle_part[t];
        if (k == part_count) continue;
        ++report.parts[k].triangles;
        facing_free[k] += std::max(0.0, facing_area[t]);
        facing_decided[k] += std::abs(facing_area[t]);
    }
    double free_all = 0, decided_all = 0;
    for (std::size_t k = 0; k < part_count; ++k) {
        report.parts[k].faces_free_side = facing_decided[k] > 0 ? facing_free[k] / facing_decided[k] : -1;
        free_all += facing_free[k], decided_all += facing_decided[k];
    }
    report.faces_free_side = decided_all > 0 ? free_all / decided_all : -1;
    const std::vector<Vec3> samples = lasmesh::sample_surface(mesh, options.mesh_samples);
    std::vector<double> distance(samples.size());
    std::vector<std::size_t> nearest(samples.size());
    tbb::parallel_for(std::size_t{0}, samples.size(), [&](std::size_t s) {
        const Vec3 world{mesh.origin[0] + samples[s][0], mesh.origin[1] + samples[s][1],
                         mesh.origin[2] + samples[s][2]};
        const Vec3 q = to_local(scene, world);
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t i : surfaces)
            if (const double d = distance_to(scene.primitives[i], q); d < best) best = d, nearest[s] = i;
        distance[s] = best;
    });
    const double per_sample = samples.empty() ? 0 : report.mesh_area / static_cast<double>(samples.size());
    std::vector<std::vector<double>> by_part(part_count);
    std::size_t floating = 0;
    for (std::size_t s = 0; s < samples.size(); ++s) {
        if (distance[s] > options.floating)
            ++floating;
        else
            by_part[part_of[nearest[s]]].push_back(distance[s]);
    }
    for (std::size_t k = 0; k < part_count; ++k) {
        report.parts[k].mesh_area = per_sample * static_cast<double>(by_part[k].size());
        const Stats s = stats_of(by_part[k]);
        report.parts[k].mean = s.mean, report.parts[k].p99 = s.p99;
    }
    const Stats all = stats_of(distance);
    report.mean = all.mean, report.median = all.median, report.p95 = all.p95, report.p99 = all.p99,
    report.max = all.max;
    report.floating_share = samples.empty() ? 0 : static_cast<double>(floating) / static_cast<double>(samples.size());

    // Truth to mesh: points spread over each primitive by its area (at least 64 on each, so a
    // post of a railing is seen), each first dropped where no scanner sees the surface.
    double total_area = 0;
    for (std::size_t i : surfaces) total_area += scene.primitives[i].weight;
    struct TruthPoint {
        Vec3 world;
        std::size_t primitive;
        bool shadow;
    };
    std::vector<TruthPoint> points;
    std::vector<std::size_t> drawn(scene.primitives.size()), kept(scene.primitives.size());
    std::uint64_t index = 0;
    for (std::size_t i : surfaces) {
        const Primitive& p = scene.primitives[i];
        drawn[i] = std::max<std::size_t>(64, static_cast<std::size_t>(std::llround(
                                                 static_cast<double>(options.truth_samples) * p.weight / total_area)));
        for (std::size_t j = 0; j < drawn[i]; ++j) {
            const Vec3 q = sample_on(p, index++);
            if (p.can_have_holes && under_footprint(scene, q)) continue;
            const Vec3 w = to_world(scene, q);
            if (!options.within.empty() && !inside(options.within, w)) continue;
            ++kept[i];
            points.push_back({w, i, p.can_have_holes && in_shadow(scene, q)});
        }
    }
    for (std::size_t i : surfaces) {
        const double seen = scene.primitives[i].weight * static_cast<double>(kept[i]) / static_cast<double>(drawn[i]);
        report.parts[part_of[i]].truth_area += seen;
        report.truth_area += seen;
    }
    std::vector<char> near(points.size(), 0);
    const lasmesh::TriangleSearch search(mesh);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4096), [&](const auto& range) {
        std::uint32_t hint = 0;
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
            const Vec3& w = points[k].world;
            const Vec3 q{w[0] - mesh.origin[0], w[1] - mesh.origin[1], w[2] - mesh.origin[2]};
            near[k] = search.distance(q, &hint) <= options.tolerance;
        }
    });
    std::vector<std::size_t> seen(part_count), covered(part_count);
    std::size_t shadow = 0, bridged = 0, seen_all = 0, covered_all = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        if (points[k].shadow) {
            ++shadow, bridged += near[k];
            continue;
        }
        const std::size_t part = part_of[points[k].primitive];
        ++seen[part], covered[part] += near[k];
        ++seen_all, covered_all += near[k];
    }
    for (std::size_t k = 0; k < part_count; ++k)
        report.parts[k].covered = seen[k] ? static_cast<double>(covered[k]) / static_cast<double>(seen[k]) : 0;
    report.covered = seen_all ? static_cast<double>(covered_all) / static_cast<double>(seen_all) : 0;
    if (shadow > 0) report.shadows_bridged = static_cast<double>(bridged) / static_cast<double>(shadow);
    return report;
}

std::string truth_table(const TruthReport& r, const TruthOptions& o) {
    auto share = [](double s) {
        char text[16] = "-";
        if (s >= 0) std::snprintf(text, sizeof text, "%.1f%%", 100 * s);
        return std::string(text);
    };
    std::string out;
    char line[256];
    std::snprintf(
        line, sizeof line,
        "| part | true m² | mesh m² | mesh / true | mean cm | p99 cm | covered (%.0f cm) | triangles | faces out |\n"
        "|---|---|---|---|---|---|---|---|---|\n",
        100 * o.tolerance);
    out += line;
    for (const PartError& p : r.parts) {
        std::snprintf(line, sizeof line, "| %s | %.1f | %.1f | %.2f | %.2f | %.1f | %.1f%% | %zu | %s |\n",
                      p.part.c_str(), p.truth_area, p.mesh_area, p.truth_area > 0 ? p.mesh_area / p.truth_area : 0,
                      100 * p.mean, 100 * p.p99, 100 * p.covered, p.triangles, share(p.faces_free_side).c_str());
        out += line;
    }
    std::snprintf(line, sizeof line, "| all | %.1f | %.1f | %.2f | %.2f | %.1f | %.1f%% | %zu | %s |\n", r.truth_area,
                  r.mesh_area, r.truth_area > 0 ? r.mesh_area / r.truth_area : 0, 100 * r.mean, 100 * r.p99,
                  100 * r.covered, r.triangles, share(r.faces_free_side).c_str());
    out += line;
    std::snprintf(line, sizeof line,
                  "\nmesh to truth: median %.2f cm, p95 %.1f cm, max %.1f cm; floating (over %.0f cm) %.3f%% of the "
                  "mesh area",
                  100 * r.median, 100 * r.p95, 100 * r.max, 100 * o.floating, 100 * r.floating_share);
    out += line;
    if (r.shadows_bridged >= 0) {
        std::snprintf(line, sizeof line, "; scan shadows bridged %.1f%%", 100 * r.shadows_bridged);
        out += line;
    }
    return out + "\n";
}

std::string truth_json(const TruthReport& r, const TruthOptions& o) {
    nlohmann::ordered_json j;
    j["tolerance"] = o.tolerance;
    j["floating_over"] = o.floating;
    j["mesh_area"] = r.mesh_area;
    j["truth_area"] = r.truth_area;
    j["triangles"] = r.triangles;
    j["mean"] = r.mean;
    j["median"] = r.median;
    j["p95"] = r.p95;
    j["p99"] = r.p99;
    j["max"] = r.max;
    j["floating_share"] = r.floating_share;
    j["covered"] = r.covered;
    j["faces_free_side"] = r.faces_free_side >= 0 ? nlohmann::ordered_json(r.faces_free_side) : nullptr;
    j["shadows_bridged"] = r.shadows_bridged >= 0 ? nlohmann::ordered_json(r.shadows_bridged) : nullptr;
    j["parts"] = nlohmann::ordered_json::array();
    for (const PartError& p : r.parts)
        j["parts"].push_back(
            {{"part", p.part},
             {"truth_area", p.truth_area},
             {"mesh_area", p.mesh_area},
             {"mean", p.mean},
             {"p99", p.p99},
             {"covered", p.covered},
             {"triangles", p.triangles},
             {"faces_free_side", p.faces_free_side >= 0 ? nlohmann::ordered_json(p.faces_free_side) : nullptr}});
    return j.dump(2) + "\n";
}

} // namespace lasgen
