// SPDX-License-Identifier: Apache-2.0
#include "mesh/seam_corners.hpp"

#include <algorithm>
#include <cmath>

namespace lasmesh {

namespace {

// Fine and coarse sample the same surface when their normals are within 60 degrees (either way
// round); farther apart, the fine plane is another surface meeting the seam (a post's side where
// the coarse sheet has the deck), whose sign the coarse value cannot give.
constexpr double same_surface_cosine = 0.5;

} // namespace

std::array<std::int64_t, 3> SeamCorners::corner_of(std::uint64_t key) const {
    const auto px = static_cast<std::uint64_t>(dims[0] + 1), py = static_cast<std::uint64_t>(dims[1] + 1);
    return {static_cast<std::int64_t>(key % px), static_cast<std::int64_t>(key / px % py),
            static_cast<std::int64_t>(key / px / py)};
}

std::uint64_t SeamCorners::key_of(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return (static_cast<std::uint64_t>(z) * static_cast<std::uint64_t>(dims[1] + 1) + static_cast<std::uint64_t>(y)) *
               static_cast<std::uint64_t>(dims[0] + 1) +
           static_cast<std::uint64_t>(x);
}

SeamCorners seam_corners_of(const std::vector<std::uint64_t>& refined, const std::array<std::int64_t, 3>& dims) {
    SeamCorners c;
    c.dims = dims;
    c.refined = refined;
    c.corners.reserve(refined.size() * 2);
    const auto dx = static_cast<std::uint64_t>(dims[0]), dy = static_cast<std::uint64_t>(dims[1]);
    for (const std::uint64_t key : refined) {
        const auto x = static_cast<std::int64_t>(key % dx), y = static_cast<std::int64_t>(key / dx % dy),
                   z = static_cast<std::int64_t>(key / dx / dy);
        for (int k = 0; k < 8; ++k) c.corners.push_back(c.key_of(x + (k & 1), y + (k >> 1 & 1), z + (k >> 2 & 1)));
    }
    std::sort(c.corners.begin(), c.corners.end());
    c.corners.erase(std::unique(c.corners.begin(), c.corners.end()), c.corners.end());
    return c;
}

SeamFaces::SeamFaces(const SeamCorners& corners) : c_(corners), cells_(corners.refined, corners.dims) {}

bool SeamFaces::refined(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return cells_.contains(static_cast<std::uint64_t>(x), static_cast<std::uint64_t>(y), static_cast<std::uint64_t>(z));
}

SeamFaces::Found SeamFaces::coarse_value(std::int64_t x, std::int64_t y, std::int64_t z,
                                         const std::array<double, 3>& normal, float& value) const {
    // Inside a coarse cell on every axis: no face of it.
    if ((x & 1) && (y & 1) && (z & 1)) return Found::off_seam;
    const std::array<std::int64_t, 3> p{x, y, z};
    // The coarse cells the point touches: on an axis where it lies on a coarse lattice plane, the
    // two either side; elsewhere the one it is in.
    std::array<std::int64_t, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
        const std::int64_t c = p[a] >> 1;
        lo[a] = (p[a] & 1) ? c : c - 1;
        hi[a] = c;
    }
    // (Past the grid's sides there are no cells, and no coarse mesh to meet.)
    bool some = false, all = true;
    for (std::int64_t cz = std::max<std::int64_t>(lo[2], 0); cz <= std::min(hi[2], c_.dims[2] - 1); ++cz)
        for (std::int64_t cy = std::max<std::int64_t>(lo[1], 0); cy <= std::min(hi[1], c_.dims[1] - 1); ++cy)
            for (std::int64_t cx = std::max<std::int64_t>(lo[0], 0); cx <= std::min(hi[0], c_.dims[0] - 1); ++cx) {
                const bool r = refined(cx, cy, cz);
                some |= r, all &= r;
            }
    if (!some || all) return Found::off_seam;
    // The coarse corners it lies between: 1 at a corner, 2 mid-edge, 4 mid-face (all of them
    // corners of a refined cell, so sampled).
    std::array<std::int64_t, 3> first{};
    std::array<int, 3> odd{};
    for (int a = 0; a < 3; ++a) first[a] = p[a] >> 1, odd[a] = static_cast<int>(p[a] & 1);
    const int count = 1 << (odd[0] + odd[1] + odd[2]);
    double sum = 0;
    bool across = false; // a corner's plane runs across the fine one: unless another is undefined
    for (int k = 0; k < 8; ++k) {
        if (((k & 1) && !odd[0]) || ((k >> 1 & 1) && !odd[1]) || ((k >> 2 & 1) && !odd[2])) continue;
        const std::array<std::int64_t, 3> q{first[0] + (k & 1), first[1] + (k >> 1 & 1), first[2] + (k >> 2 & 1)};
        const std::uint64_t key = c_.key_of(q[0], q[1], q[2]);
        const auto at = std::lower_bound(c_.corners.begin(), c_.corners.end(), key);
        if (at == c_.corners.end() || *at != key) return Found::undefined; // not sampled: cannot be
        const auto i = static_cast<std::size_t>(at - c_.corners.begin());
        const std::uint8_t flags = c_.flags[i];
        if (!(flags & SeamCorners::defined)) return Found::undefined;
        // The coarse edges within the span run up an odd axis from a corner with that axis' bit
        // clear (a face's four edges from its corners 0, 0, 1 and 2): a rejected crossing leaves
        // the coarse cube next to the seam unmeshed, and so must the fine one be.
        for (int a = 0; a < 3; ++a)
            if (odd[a] && !(k >> a & 1) && (flags >> (1 + a) & 1)) return Found::undefined;
        const std::array<float, 3>& n = c_.normal[i];
        const double along = n[0] * normal[0] + n[1] * normal[1] + n[2] * normal[2];
        across = across || std::abs(along) < same_surface_cosine;
        sum += along > 0 ? c_.value[i] : -c_.value[i];
    }
    if (across) return Found::off_seam;
    value = static_cast<float>(sum / count);
    return Found::value;
}

} // namespace lasmesh
