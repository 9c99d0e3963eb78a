// SPDX-License-Identifier: Apache-2.0
// thin_cells: surface cells whose neighbourhood is a line; blocks_around: the cells or bricks near them.
#include "grid/thin_parts.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <tuple>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace lasmesh {

std::array<double, 3> symmetric_eigenvalues(const std::array<std::array<double, 3>, 3>& a) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double q = (a[0][0] + a[1][1] + a[2][2]) / 3;
    std::array<double, 3> e{a[0][0], a[1][1], a[2][2]};
    if (off > 0) {
        const double d0 = a[0][0] - q, d1 = a[1][1] - q, d2 = a[2][2] - q;
        const double p = std::sqrt((d0 * d0 + d1 * d1 + d2 * d2 + 2 * off) / 6);
        if (p > 0) {
            // B = (A - q I) / p; det(B) / 2 = cos(3 phi).
            const double b00 = d0 / p, b11 = d1 / p, b22 = d2 / p, b01 = a[0][1] / p, b02 = a[0][2] / p,
                         b12 = a[1][2] / p;
            const double det =
                b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
            const double phi = std::acos(std::clamp(det / 2, -1.0, 1.0)) / 3;
            e[0] = q + 2 * p * std::cos(phi);
            e[2] = q + 2 * p * std::cos(phi + 2 * std::numbers::pi / 3);
            e[1] = 3 * q - e[0] - e[2];
        }
    }
    std::sort(e.begin(), e.end(), std::greater<>());
    return e;
}

namespace {

// Cells whose centroids lie this many cells from a line through a thin cell's neighbours are on
// it (under the first) or beside it (up to the second): a plane's next row lies 1-1.5 cells off
// (nearest past its edge's sliver, farthest past a half-full cell); a rail's cells lie its radius
// and the noise away (on the deck, 3,379 of the railings' 3,382 thin cells stay thin at 2M
// points, all 19,155 at 20M).
constexpr double plane_edge_near = 0.9, plane_edge_far = 2.0;

// The unit eigenvector of the symmetric `a` for its eigenvalue `e` (the largest: a simple one): the
// longest cross product of two rows of a - e I, which are orthogonal to it.
Vec3 principal_direction(const std::array<std::array<double, 3>, 3>& a, double e) {
    std::array<Vec3, 3> row{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) row[i][j] = a[i][j] - (i == j ? e : 0);
    const auto cross = [](const Vec3& u, const Vec3& v) {
        return Vec3{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    };
    Vec3 best{};
    double longest = 0;
    for (const auto& [i, j] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}}) {
        const Vec3 c = cross(row[i], row[j]);
        const double l = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
        if (l > longest) longest = l, best = c;
    }
    if (!(longest > 0)) return Vec3{1, 0, 0};
    const double l = std::sqrt(longest);
    return Vec3{best[0] / l, best[1] / l, best[2] / l};
}

} // namespace

std::vector<std::array<std::int64_t, 3>> thin_cells(const CellGrid& grid, double iso) {
    const auto surface = [&](std::int64_t x, std::int64_t y, std::int64_t z) -> const CellSums* {
        const CellSums* c = grid.find(x, y, z);
        return c && static_cast<double>(c->count) > iso ? c : nullptr;
    };
    const double h = grid.spec.cell_size;
    const auto is_thin = [&](const std::array<std::int64_t, 3>& at) {
        std::array<Vec3, 27> centroid;
        std::array<double, 27> weight;
        std::size_t n = 0;
        for (std::int64_t dz = -1; dz <= 1; ++dz)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dx = -1; dx <= 1; ++dx)
                    if (const CellSums* c = surface(at[0] + dx, at[1] + dy, at[2] + dz)) {
                        centroid[n] = grid.centroid({at[0] + dx, at[1] + dy, at[2] + dz}, *c);
                        weight[n++] = static_cast<double>(c->count);
                    }
        if (n < 3) return false;
        double total = 0;
        Vec3 mean{};
        for (std::size_t k = 0; k < n; ++k) {
            total += weight[k];
            for (int i = 0; i < 3; ++i) mean[i] += weight[k] * centroid[k][i];
        }
        for (double& m : mean) m /= total;
        std::array<std::array<double, 3>, 3> cov{};
        for (std::size_t k = 0; k < n; ++k)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    cov[i][j] += weight[k] * (centroid[k][i] - mean[i]) * (centroid[k][j] - mean[j]);
        const std::array<double, 3> e = symmetric_eigenvalues(cov);
        if (!(e[1] < thin_line_ratio * e[0])) return false;
        // A plane's edge: where the plane ends part-way through a row of cells, their centroids
        // crowd the next row's, and the two rows read as a line. The plane goes on beside it: in
        // the cells two around, a row of cells about one cell from the line, as full as the
        // line's, along most of its length (3 of 5 steps along it). A post under a rail, or a
        // plate past a gap, is beside it at one step, or farther off.
        const Vec3 d = principal_direction(cov, e[0]);
        std::array<double, 5> on_line{}, beside{};
        for (std::int64_t dz = -2; dz <= 2; ++dz)
            for (std::int64_t dy = -2; dy <= 2; ++dy)
                for (std::int64_t dx = -2; dx <= 2; ++dx) {
                    const std::array<std::int64_t, 3> q{at[0] + dx, at[1] + dy, at[2] + dz};
                    const CellSums* c = surface(q[0], q[1], q[2]);
                    if (!c) continue;
                    const Vec3 p = grid.centroid(q, *c);
                    const Vec3 r{p[0] - mean[0], p[1] - mean[1], p[2] - mean[2]};
                    const double along = r[0] * d[0] + r[1] * d[1] + r[2] * d[2];
                    const double across =
                        std::sqrt(std::max(0.0, r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - along * along));
                    const auto step = static_cast<std::size_t>(std::clamp(std::lround(along / h), -2L, 2L) + 2);
                    if (across < plane_edge_near * h)
                        on_line[step] += static_cast<double>(c->count);
                    else if (across < plane_edge_far * h)
                        beside[step] += static_cast<double>(c->count);
                }
        int sided = 0;
        for (std::size_t k = 0; k < 5; ++k) sided += beside[k] > 0 && beside[k] >= 0.5 * on_line[k];
        return sided < 3;
    };
    // Brick by brick in parallel, each brick's thin cells in the order of their bits, the bricks
    // in ascending order: the same list for any thread count.
    std::vector<std::vector<std::array<std::int64_t, 3>>> per_brick(grid.brick_keys.size());
    tbb::parallel_for(std::size_t{0}, grid.brick_keys.size(), [&](std::size_t b) {
        std::uint64_t record = grid.brick_first[b];
        for (std::uint64_t mask = grid.brick_masks[b]; mask != 0; mask &= mask - 1, ++record) {
            if (!(static_cast<double>(grid.cells[record].count) > iso)) continue;
            const std::array<std::int64_t, 3> at =
                grid.cell_in_brick(grid.brick_keys[b], static_cast<unsigned>(std::countr_zero(mask)));
            if (is_thin(at)) per_brick[b].push_back(at);
        }
    });
    std::vector<std::array<std::int64_t, 3>> thin;
    for (const auto& cells : per_brick) thin.insert(thin.end(), cells.begin(), cells.end());
    const auto z_y_x = [](const auto& a, const auto& b) {
        return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]);
    };
    std::sort(thin.begin(), thin.end(), z_y_x);
    // The cells between thin cells (a junction, a gap along a rail): a surface cell with thin
    // cells on opposite sides of it within two cells, their offsets at more than a right angle.
    // Left coarse, such a cell's sheet meets the fine tubes on both sides with borders that
    // cannot be joined (a fin against a ring), and a crack runs round each.
    const auto is_thin_cell = [&](const std::array<std::int64_t, 3>& c) {
        return std::binary_search(thin.begin(), thin.end(), c, z_y_x);
    };
    const std::array<std::int64_t, 3> dims{grid.spec.dims[0], grid.spec.dims[1], grid.spec.dims[2]};
    const auto d0 = static_cast<std::uint64_t>(dims[0]), d1 = static_cast<std::uint64_t>(dims[1]);
    std::vector<std::array<std::int64_t, 3>> between;
    for (const std::uint64_t key : blocks_around(thin, dims, 0, 2)) {
        const std::array<std::int64_t, 3> c{std::int64_t(key % d0), std::int64_t(key / d0 % d1),
                                            std::int64_t(key / d0 / d1)};
        if (!surface(c[0], c[1], c[2]) || is_thin_cell(c)) continue;
        std::array<std::array<std::int64_t, 3>, 125> offsets;
        std::size_t n = 0;
        for (std::int64_t dz = -2; dz <= 2; ++dz)
            for (std::int64_t dy = -2; dy <= 2; ++dy)
                for (std::int64_t dx = -2; dx <= 2; ++dx)
                    if (is_thin_cell({c[0] + dx, c[1] + dy, c[2] + dz})) offsets[n++] = {dx, dy, dz};
        bool opposite = false;
        for (std::size_t i = 0; i < n && !opposite; ++i)
            for (std::size_t j = i + 1; j < n && !opposite; ++j)
                opposite =
                    offsets[i][0] * offsets[j][0] + offsets[i][1] * offsets[j][1] + offsets[i][2] * offsets[j][2] < 0;
        if (opposite) between.push_back(c);
    }
    thin.insert(thin.end(), between.begin(), between.end());
    std::sort(thin.begin(), thin.end(), z_y_x);
    return thin;
}

std::vector<std::uint64_t> blocks_around(const std::vector<std::array<std::int64_t, 3>>& cells,
                                         const std::array<std::int64_t, 3>& count, int shift, std::int64_t reach) {
    std::vector<std::uint64_t> keys;
    for (const std::array<std::int64_t, 3>& at : cells) {
        const std::array<std::int64_t, 3> block{at[0] >> shift, at[1] >> shift, at[2] >> shift};
        for (std::int64_t dz = -reach; dz <= reach; ++dz)
            for (std::int64_t dy = -reach; dy <= reach; ++dy)
                for (std::int64_t dx = -reach; dx <= reach; ++dx) {
                    const std::int64_t x = block[0] + dx, y = block[1] + dy, z = block[2] + dz;
                    if (x < 0 || y < 0 || z < 0 || x >= count[0] || y >= count[1] || z >= count[2]) continue;
                    keys.push_back((std::uint64_t(z) * std::uint64_t(count[1]) + std::uint64_t(y)) *
                                       std::uint64_t(count[0]) +
                                   std::uint64_t(x));
                }
    }
    tbb::parallel_sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return keys;
}

} // namespace lasmesh
