// SPDX-License-Identifier: Apache-2.0
#include "measure/level_error.hpp"

#include "measure/mesh_distance.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

namespace lasmesh {

namespace {

// The 99th percentile of the distances from `samples` points spread over `from`'s surface (by
// area: a small stray piece weighs what its area does, not what its vertex count does) to `to`.
double percentile_99(const Mesh& from, const Mesh& to, std::size_t samples) {
    const TriangleSearch search(to);
    const std::vector<Vec3> points = sample_surface(from, samples);
    std::vector<double> distance(points.size());
    tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
        const Vec3 in_to{points[i][0] + from.origin[0] - to.origin[0], points[i][1] + from.origin[1] - to.origin[1],
                         points[i][2] + from.origin[2] - to.origin[2]};
        distance[i] = search.distance(in_to);
    });
    if (distance.empty()) return 0;
    const std::size_t at = std::min(distance.size() - 1, distance.size() * 99 / 100);
    std::nth_element(distance.begin(), distance.begin() + static_cast<std::ptrdiff_t>(at), distance.end());
    return distance[at];
}

} // namespace

double level_error(const Mesh& coarse, const Mesh& fine, std::size_t samples) {
    if (coarse.triangles.empty() || fine.triangles.empty() || samples == 0) return 0;
    return std::max(percentile_99(coarse, fine, samples), percentile_99(fine, coarse, samples));
}

std::size_t remove_far_from(Mesh& coarse, const Mesh& fine, double distance) {
    if (fine.triangles.empty()) return 0;
    const TriangleSearch search(fine);
    std::vector<char> keep(coarse.triangles.size());
    tbb::parallel_for(std::size_t{0}, coarse.triangles.size(), [&](std::size_t t) {
        Vec3 centroid{};
        for (const std::uint32_t v : coarse.triangles[t])
            for (int a = 0; a < 3; ++a) centroid[a] += coarse.positions[v][a] / 3.0;
        for (int a = 0; a < 3; ++a) centroid[a] += coarse.origin[a] - fine.origin[a];
        keep[t] = search.distance(centroid) <= distance;
    });
    std::size_t kept = 0;
    for (std::size_t t = 0; t < coarse.triangles.size(); ++t)
        if (keep[t]) coarse.triangles[kept++] = coarse.triangles[t];
    const std::size_t removed = coarse.triangles.size() - kept;
    coarse.triangles.resize(kept);
    return removed;
}

} // namespace lasmesh
