// SPDX-License-Identifier: Apache-2.0
#include "measure/level_error.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace lasmesh {

namespace {

// The 99th percentile of `distance` (reordered); 0 when empty.
double percentile_99(std::vector<double>& distance) {
    if (distance.empty()) return 0;
    const std::size_t at = std::min(distance.size() - 1, distance.size() * 99 / 100);
    std::nth_element(distance.begin(), distance.begin() + static_cast<std::ptrdiff_t>(at), distance.end());
    return distance[at];
}

// The distances from `points` (in the frame with `from_origin`) to `search`'s mesh (with `to_origin`).
std::vector<double> distances(const std::vector<Vec3>& points, const Vec3& from_origin, const TriangleSearch& search,
                              const Vec3& to_origin) {
    std::vector<double> distance(points.size());
    tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
        Vec3 p;
        for (int a = 0; a < 3; ++a) p[a] = points[i][a] + from_origin[a] - to_origin[a];
        distance[i] = search.distance(p);
    });
    return distance;
}

} // namespace

FinestLevel::FinestLevel(const Mesh& fine, std::size_t samples)
    : fine_(fine), samples_(samples), search_(fine), points_(sample_surface(fine, samples)) {}

double FinestLevel::error(const Mesh& coarse) const {
    if (coarse.triangles.empty() || fine_.triangles.empty() || samples_ == 0) return 0;
    std::vector<double> coarse_to_fine =
        distances(sample_surface(coarse, samples_), coarse.origin, search_, fine_.origin);
    std::vector<double> fine_to_coarse = distances(points_, fine_.origin, TriangleSearch(coarse), coarse.origin);
    return std::max(percentile_99(coarse_to_fine), percentile_99(fine_to_coarse));
}

std::size_t FinestLevel::remove_far(Mesh& coarse, double distance) const {
    if (fine_.triangles.empty()) return 0;
    std::vector<char> keep(coarse.triangles.size());
    tbb::parallel_for(std::size_t{0}, coarse.triangles.size(), [&](std::size_t t) {
        Vec3 centroid{};
        for (const std::uint32_t v : coarse.triangles[t])
            for (int a = 0; a < 3; ++a) centroid[a] += coarse.positions[v][a] / 3.0;
        for (int a = 0; a < 3; ++a) centroid[a] += coarse.origin[a] - fine_.origin[a];
        keep[t] = search_.distance(centroid) <= distance;
    });
    std::size_t kept = 0;
    for (std::size_t t = 0; t < coarse.triangles.size(); ++t)
        if (keep[t]) coarse.triangles[kept++] = coarse.triangles[t];
    const std::size_t removed = coarse.triangles.size() - kept;
    coarse.triangles.resize(kept);
    return removed;
}

} // namespace lasmesh
