// SPDX-License-Identifier: Apache-2.0
// check_simplified: what a simplification did to the surface (tests, tools/simplify_bench).
#include "mesh/simplify_check.hpp"

#include <algorithm>
#include <cmath>
#include <map>

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
    for (std::size_t i = 1; i < directed.size(); ++i)
        bad += directed[i] == directed[i - 1] && (i == 1 || directed[i - 2] != directed[i]);
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
