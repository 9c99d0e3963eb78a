// Simplification with meshoptimizer (Debian's libmeshoptimizer-dev, 0.18). Its error is relative
// to the mesh extent (meshopt_simplifyScale), so the bound in file units is divided by that scale.
#include "lasmesh/mesh/simplify.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <limits>

namespace lasmesh {

namespace {

// Drops the vertices no triangle uses and renumbers the rest in their old order.
void remove_unused_vertices(Mesh& mesh) {
    constexpr std::uint32_t unused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> remap(mesh.positions.size(), unused);
    for (const auto& t : mesh.triangles)
        for (const std::uint32_t v : t) remap[v] = 0;
    std::uint32_t kept = 0;
    for (std::size_t v = 0; v < remap.size(); ++v) {
        if (remap[v] == unused) continue;
        remap[v] = kept;
        mesh.positions[kept] = mesh.positions[v];
        if (!mesh.colors.empty()) mesh.colors[kept] = mesh.colors[v];
        if (!mesh.normals.empty()) mesh.normals[kept] = mesh.normals[v];
        ++kept;
    }
    mesh.positions.resize(kept);
    if (!mesh.colors.empty()) mesh.colors.resize(kept);
    if (!mesh.normals.empty()) mesh.normals.resize(kept);
    for (auto& t : mesh.triangles)
        for (std::uint32_t& v : t) v = remap[v];
}

} // namespace

SimplifyReport simplify_mesh(Mesh& mesh, const SimplifyOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    SimplifyReport report;
    report.triangles_before = report.triangles_after = mesh.triangles.size();
    report.error = options.error;
    if (!(options.error > 0) || mesh.triangles.empty()) return report;

    const float* positions = mesh.positions[0].data();
    const std::size_t stride = sizeof mesh.positions[0];
    const float scale = meshopt_simplifyScale(positions, mesh.positions.size(), stride);
    if (!(scale > 0)) return report;
    const auto* indices = mesh.triangles[0].data();
    const std::size_t index_count = 3 * mesh.triangles.size();
    std::vector<unsigned int> out(index_count);
    float result_error = 0;
    // Target 0 triangles: only the error bound stops the collapses.
    const std::size_t kept = meshopt_simplify(out.data(), indices, index_count, positions, mesh.positions.size(), stride, 0,
                                              static_cast<float>(options.error / scale),
                                              options.lock_border ? meshopt_SimplifyLockBorder : 0, &result_error);
    mesh.triangles.resize(kept / 3);
    for (std::size_t t = 0; t < kept / 3; ++t) mesh.triangles[t] = {out[3 * t], out[3 * t + 1], out[3 * t + 2]};
    remove_unused_vertices(mesh);

    report.triangles_after = mesh.triangles.size();
    report.result_error = double(result_error) * scale;
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace lasmesh

namespace lasmesh {

namespace {

std::array<double, 3> face_cross(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const auto &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
    const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}

// Area next to nothing: the cross product is below a millionth of the longest edge squared.
bool zero_area(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const auto n = face_cross(m, t);
    double longest = 0;
    for (int k = 0; k < 3; ++k) {
        const auto &a = m.positions[t[k]], &b = m.positions[t[(k + 1) % 3]];
        double d = 0;
        for (int i = 0; i < 3; ++i) d += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
        longest = std::max(longest, d);
    }
    return std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) <= 1e-6 * longest;
}

std::size_t count_bad_edges(const Mesh& m) {
    std::vector<std::uint64_t> directed, undirected;
    directed.reserve(3 * m.triangles.size());
    undirected.reserve(3 * m.triangles.size());
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t a = t[k], b = t[(k + 1) % 3];
            directed.push_back(a << 32 | b);
            undirected.push_back(std::min(a, b) << 32 | std::max(a, b));
        }
    std::size_t bad = 0;
    std::sort(directed.begin(), directed.end());
    for (std::size_t i = 1; i < directed.size(); ++i) bad += directed[i] == directed[i - 1] && (i == 1 || directed[i - 2] != directed[i]);
    std::sort(undirected.begin(), undirected.end());
    for (std::size_t i = 2; i < undirected.size(); ++i)
        bad += undirected[i] == undirected[i - 2] && (i == 2 || undirected[i - 3] != undirected[i]);
    return bad;
}

} // namespace

SimplifyCheck check_simplified(const Mesh& original, const Mesh& simplified) {
    SimplifyCheck check;
    std::map<std::array<float, 3>, std::array<double, 3>> normal_at;
    for (const auto& t : original.triangles) {
        const auto n = face_cross(original, t);
        for (const std::uint32_t v : t) {
            auto& s = normal_at[original.positions[v]];
            for (int k = 0; k < 3; ++k) s[k] += n[k];
        }
    }
    std::vector<std::array<double, 3>> reference(simplified.positions.size(), {0, 0, 0});
    for (std::size_t v = 0; v < simplified.positions.size(); ++v) {
        const auto it = normal_at.find(simplified.positions[v]);
        if (it == normal_at.end()) {
            ++check.unmatched_vertices;
            continue;
        }
        const auto& s = it->second;
        const double length = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
        if (length > 0) reference[v] = {s[0] / length, s[1] / length, s[2] / length};
    }
    // Faces the simplification left as they were do not count: the extraction folds a few.
    using Corners = std::array<float, 9>;
    const auto corners = [](const Mesh& m, const std::array<std::uint32_t, 3>& t) {
        int first = 0; // rotated to start at the smallest position: the same face, same winding
        for (int k = 1; k < 3; ++k)
            if (m.positions[t[k]] < m.positions[t[first]]) first = k;
        Corners c;
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i) c[3 * k + i] = m.positions[t[(first + k) % 3]][i];
        return c;
    };
    std::vector<Corners> kept;
    kept.reserve(original.triangles.size());
    for (const auto& t : original.triangles) kept.push_back(corners(original, t));
    std::sort(kept.begin(), kept.end());
    for (const auto& t : simplified.triangles) {
        const auto n = face_cross(simplified, t);
        double dot = 0;
        for (const std::uint32_t v : t)
            for (int k = 0; k < 3; ++k) dot += n[k] * reference[v][k];
        check.flipped += dot < 0 && !std::binary_search(kept.begin(), kept.end(), corners(simplified, t));
        check.zero_area += zero_area(simplified, t);
    }
    for (const auto& t : original.triangles) check.zero_area_before += zero_area(original, t);
    check.bad_edges = count_bad_edges(simplified);
    check.bad_edges_before = count_bad_edges(original);
    return check;
}

} // namespace lasmesh
