// SPDX-License-Identifier: Apache-2.0
// extract_sheet: tangent planes from the cells' moments, oriented by a spanning tree, sampled as a
// signed distance at the cell corners and contoured by sparse marching cubes.
#include "mesh/surface_sheet.hpp"

#include "grid/thin_parts.hpp"

#include "lasmesh/normals.hpp"
#include "mesh/mesh_edit.hpp"
#include "mesh/outside_space.hpp"
#include "sparse_marching_cubes.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <queue>

namespace lasmesh {

namespace {

using Vec = std::array<double, 3>;
constexpr std::uint32_t no_plane = UINT32_MAX;

double dot(const Vec& a, const Vec& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// The normal of the plane that fits a covariance best: the unit eigenvector of its smallest
// eigenvalue, by cyclic Jacobi rotations (deterministic, and accurate for the nearly flat
// covariances of surfaces).
Vec plane_normal(std::array<std::array<double, 3>, 3> a) {
    std::array<std::array<double, 3>, 3> v{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    for (int sweep = 0; sweep < 16; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double scale = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-24 * scale || off == 0) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                const double t = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 3; ++k) { // a = J^T a J, v = v J
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    int m = 0;
    for (int i = 1; i < 3; ++i)
        if (a[i][i] < a[m][m]) m = i;
    const Vec n{v[0][m], v[1][m], v[2][m]};
    const double length = std::sqrt(dot(n, n));
    return length > 0 ? Vec{n[0] / length, n[1] / length, n[2] / length} : Vec{0, 0, 1};
}

// Two unit vectors along the plane of unit normal n, at right angles: the lattice axes least along
// n, in that order, with their parts along n (and the first) taken away. They depend on n's line
// only, not on which way it points, so they stay the same when the sheet's orientation turns n.
std::array<Vec, 2> along_plane_axes(const Vec& n) {
    std::array<int, 3> axis{0, 1, 2};
    std::stable_sort(axis.begin(), axis.end(), [&](int a, int b) { return std::abs(n[a]) < std::abs(n[b]); });
    std::array<Vec, 2> t{};
    for (int k = 0; k < 2; ++k) {
        Vec e{};
        e[axis[k]] = 1;
        const double on_n = dot(e, n), on_first = k == 1 ? dot(e, t[0]) : 0.0;
        for (int c = 0; c < 3; ++c) e[c] -= on_n * n[c] + on_first * t[0][c];
        const double length = std::sqrt(dot(e, e));
        for (int c = 0; c < 3; ++c) t[k][c] = e[c] / length;
    }
    return t;
}

// The surface round a line of cells (a rail, a post, a thin pipe): a cylinder.
struct Tube {
    Vec point{};     // on the axis, relative to the grid origin
    Vec direction{}; // unit
    double radius = 0;
};

// The distance from `at` to the tube's surface: negative inside.
double surface_distance(const Tube& t, const Vec& at) {
    const Vec r{at[0] - t.point[0], at[1] - t.point[1], at[2] - t.point[2]};
    const double along = r[0] * t.direction[0] + r[1] * t.direction[1] + r[2] * t.direction[2];
    return std::sqrt(std::max(0.0, r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - along * along)) - t.radius;
}

// The surface cells and their tangent planes.
struct Planes {
    const CellGrid& grid;
    std::vector<std::uint32_t> of_record; // per grid.cells record: its plane, or no_plane
    std::vector<std::array<std::int64_t, 3>> cell;
    std::vector<Vec> centroid; // relative to the grid origin
    std::vector<Vec> normal;
    std::vector<std::uint64_t> count;
    std::vector<Rgb8> color; // the cell's mean colour (empty without colour)
    // The scatter of each cell's points about its centroid (CellGrid::scatter; empty when the grid
    // holds no exact moments), until the thickness is estimated.
    std::vector<std::array<float, 6>> scatter;
    // The covariance of each cell's points along its plane (t1 t1, t2 t2, t1 t2 with
    // along_plane_axes' t1, t2): how far its points spread each way along it, kept from the
    // scatter for where a sheet ends (SheetField); empty when the grid holds no exact moments.
    std::vector<std::array<float, 3>> spread_along;
    // Half the distance between the two faces of a plate scanned on both, per plane; 0: one face
    // (empty: none found).
    std::vector<float> half_thickness;
    std::vector<Tube> tube; // with LinearParts::tubes: per plane, its tube (radius 0: none)
    // With LinearParts::tubes, per plane that is no tube but lies on tubes around it (a junction of
    // a rail and a post, a tube's end): those tubes' cells, no_plane after the last.
    std::vector<std::array<std::uint32_t, 4>> joins;

    bool two_faced(std::uint32_t p) const { return !half_thickness.empty() && half_thickness[p] > 0; }
    // Whether p's surface is a tube or a union of tubes rather than a plane.
    bool tubular(std::uint32_t p) const { return !tube.empty() && (tube[p].radius > 0 || joins[p][0] != no_plane); }
    // The distance from `at` to the surface of p's tube, or of the nearest of the tubes it joins,
    // and that tube; no tube when p has none.
    std::pair<double, const Tube*> tube_distance(std::uint32_t p, const Vec& at) const {
        if (tube.empty()) return {0, nullptr};
        if (tube[p].radius > 0) return {surface_distance(tube[p], at), &tube[p]};
        std::pair<double, const Tube*> best{0, nullptr};
        for (const std::uint32_t q : joins[p]) {
            if (q == no_plane) break;
            const double d = surface_distance(tube[q], at);
            if (!best.second || d < best.first) best = {d, &tube[q]};
        }
        return best;
    }

    // Everything the extraction needs of the grid's cells, so they can go once this is made.
    Planes(const CellGrid& g, double iso) : grid(g), of_record(g.cells.size(), no_plane) {
        const bool moments = g.moments_exact();
        // Counted first: grown by doubling, these would hold up to twice the memory they need at
        // the extraction's peak, while the grid's cells are still here.
        const auto surface = static_cast<std::size_t>(std::count_if(
            g.cells.begin(), g.cells.end(), [&](const CellSums& c) { return static_cast<double>(c.count) > iso; }));
        cell.reserve(surface), centroid.reserve(surface), count.reserve(surface);
        if (g.has_color()) color.reserve(surface);
        if (moments) scatter.reserve(surface);
        g.for_each_cell([&](const std::array<std::int64_t, 3>& at, std::uint64_t r) {
            if (!(static_cast<double>(g.cells[r].count) > iso)) return;
            of_record[r] = static_cast<std::uint32_t>(cell.size());
            cell.push_back(at);
            centroid.push_back(g.centroid(at, g.cells[r]));
            count.push_back(g.cells[r].count);
            if (g.has_color()) color.push_back(g.mean_color(g.cells[r]));
            if (moments) {
                const std::array<double, 6> m = g.scatter(g.cells[r]);
                scatter.push_back({float(m[0]), float(m[1]), float(m[2]), float(m[3]), float(m[4]), float(m[5])});
            }
        });
        normal.resize(cell.size());
    }
    // Planes made already (UnfacedPlanes, in the grid's order), found through `index`: a grid of
    // no cells but their bricks, whose records are the planes.
    Planes(const CellGrid& index, UnfacedPlanes&& made)
        : grid(index), centroid(std::move(made.centroid)), normal(std::move(made.normal)), count(std::move(made.count)),
          half_thickness(std::move(made.half_thickness)) {
        of_record.resize(centroid.size());
        cell.reserve(centroid.size());
        index.for_each_cell([&](const std::array<std::int64_t, 3>& at, std::uint64_t r) {
            of_record[r] = static_cast<std::uint32_t>(r);
            cell.push_back(at);
        });
    }
    // From the grid's brick index only (its cells may be gone).
    std::uint32_t at(std::int64_t x, std::int64_t y, std::int64_t z) const {
        const std::uint64_t r = grid.record_of(x, y, z);
        return r == CellGrid::no_record ? no_plane : of_record[r];
    }
    // The planes of the cells within `reach` of p's on every axis, p's own among them, z slowest.
    template <class Visit>
    void for_each_within(std::uint32_t p, int reach, Visit visit) const {
        const auto& c = cell[p];
        for (int dz = -reach; dz <= reach; ++dz)
            for (int dy = -reach; dy <= reach; ++dy)
                for (int dx = -reach; dx <= reach; ++dx) {
                    const std::uint32_t q = at(c[0] + dx, c[1] + dy, c[2] + dz);
                    if (q != no_plane) visit(q);
                }
    }
    template <class Visit>
    void for_each_neighbour(std::uint32_t p, Visit visit) const {
        for_each_within(p, 1, [&](std::uint32_t q) {
            if (q != p) visit(q);
        });
    }
};

// Step 1: each plane's normal from the count-weighted centroids of its 3 x 3 x 3 surface cells
// (the neighbours looked up once: two passes over them, the mean first, keep the sums exact as
// written, and the look-ups were half the step's time).
void estimate_normals(Planes& planes) {
    tbb::parallel_for(std::size_t{0}, planes.cell.size(), [&](std::size_t p) {
        std::array<std::uint32_t, 27> near;
        std::size_t count = 0;
        near[count++] = static_cast<std::uint32_t>(p);
        planes.for_each_neighbour(static_cast<std::uint32_t>(p), [&](std::uint32_t q) { near[count++] = q; });
        double total = 0;
        Vec mean{};
        for (std::size_t k = 0; k < count; ++k) {
            const double w = static_cast<double>(planes.count[near[k]]);
            const Vec& c = planes.centroid[near[k]];
            total += w;
            for (int i = 0; i < 3; ++i) mean[i] += w * c[i];
        }
        for (double& m : mean) m /= total;
        std::array<std::array<double, 3>, 3> cov{};
        for (std::size_t k = 0; k < count; ++k) {
            const double w = static_cast<double>(planes.count[near[k]]);
            const Vec& c = planes.centroid[near[k]];
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) cov[i][j] += w * (c[i] - mean[i]) * (c[j] - mean[j]);
        }
        planes.normal[p] = plane_normal(cov);
    });
}

// Step 1b: a scanned surface that runs near a face between two cells has its points split
// between them, and each cell's centroid is the mean of one tail of the scan's noise (a
// truncated normal: up to 0.8 sigma off the surface at the face itself), so the planes of the two
// cells sit on either side of the surface and the sheet zigzags between them. Each plane is
// therefore moved along its normal to the count-weighted mean offset of its cell and of the
// neighbouring cells across its plane from it: those whose centroid lies within a quarter of a
// cell of its normal line and half a cell of its plane, whose normal is within 26 degrees of its
// own, and that are no tube (the other tails of the same layer of points, not the cells along
// the plane, another surface or a rail). Their points together are the whole layer, whose mean
// lies on the surface. Within half a cell of the normal line, a pipe a cell or two across sank
// toward its axis at coarse grids (the deck at 25 cm cells lost a tenth of its pipes' area). On
// the 181M-point deck the mesh went from 0.82 to 0.40 cm off the true surfaces on average and
// from 197,295 to 132,284 triangles.
void pool_split_layers(Planes& planes, double h) {
    std::vector<Vec> moved(planes.centroid.size());
    tbb::parallel_for(std::size_t{0}, planes.cell.size(), [&](std::size_t p) {
        const Vec& n = planes.normal[p];
        const Vec& c = planes.centroid[p];
        if (planes.tubular(static_cast<std::uint32_t>(p)) || planes.two_faced(static_cast<std::uint32_t>(p))) {
            moved[p] = c; // a plate's plane is at its points' middle already (estimate_thickness)
            return;
        }
        double total = static_cast<double>(planes.count[p]), offset = 0;
        planes.for_each_neighbour(static_cast<std::uint32_t>(p), [&](std::uint32_t q) {
            const Vec& m = planes.centroid[q];
            const Vec d{m[0] - c[0], m[1] - c[1], m[2] - c[2]};
            const double along = dot(n, d);
            const Vec across{d[0] - along * n[0], d[1] - along * n[1], d[2] - along * n[2]};
            if (std::abs(along) > 0.5 * h || dot(across, across) > h * h / 16 ||
                std::abs(dot(n, planes.normal[q])) < 0.9 || planes.tubular(q) || planes.two_faced(q))
                return;
            const double w = static_cast<double>(planes.count[q]);
            total += w, offset += w * along;
        });
        const double shift = offset / total;
        moved[p] = {c[0] + shift * n[0], c[1] + shift * n[1], c[2] + shift * n[2]};
    });
    planes.centroid = std::move(moved);
}

// The spread of the points along each plane's normal, with the layer's points (no tube: 0
// points) and their mean's offset from the plane along it: the cells met along its normal line
// within 2.5 cells either way (sampled every half cell), parallel to it, no tube, their centroids
// within half a cell of the line; their points' variance along the normal about their common mean
// (each cell's own scatter, CellGrid::scatter, and the cells' offsets together). Measured before
// the layers are pooled (the centroids are the cells' own). A band of noisy points 10 cm wide
// spans three 6 cm cells: the 3 x 3 x 3 around an edge cell of it miss the far one, and its spread
// came out a third short.
void layer_spreads(const Planes& planes, double h, std::vector<double>& spread, std::vector<double>& points,
                   std::vector<double>& middle) {
    const std::size_t count = planes.cell.size();
    spread.assign(count, 0), points.assign(count, 0), middle.assign(count, 0);
    const auto along_normal = [&](std::uint32_t q, const Vec& n) {
        const auto& m = planes.scatter[q];
        return m[0] * n[0] * n[0] + m[1] * n[1] * n[1] + m[2] * n[2] * n[2] +
               2 * (m[3] * n[0] * n[1] + m[4] * n[0] * n[2] + m[5] * n[1] * n[2]);
    };
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t p) {
        if (planes.tubular(static_cast<std::uint32_t>(p))) return;
        const Vec& n = planes.normal[p];
        const Vec& c = planes.centroid[p];
        std::array<std::uint32_t, 11> layer;
        std::size_t in_layer = 0;
        layer[in_layer++] = static_cast<std::uint32_t>(p);
        for (int k = -5; k <= 5; ++k) {
            if (k == 0) continue;
            std::array<std::int64_t, 3> at{};
            for (int a = 0; a < 3; ++a) at[a] = static_cast<std::int64_t>(std::floor((c[a] + 0.5 * k * h * n[a]) / h));
            const std::uint32_t q = planes.at(at[0], at[1], at[2]);
            if (q == no_plane || std::find(layer.begin(), layer.begin() + in_layer, q) != layer.begin() + in_layer)
                continue;
            const Vec& m = planes.centroid[q];
            const Vec d{m[0] - c[0], m[1] - c[1], m[2] - c[2]};
            const double along = dot(n, d);
            const Vec across{d[0] - along * n[0], d[1] - along * n[1], d[2] - along * n[2]};
            if (std::abs(along) > 2.5 * h || dot(across, across) > h * h / 4 ||
                std::abs(dot(n, planes.normal[q])) < 0.9 || planes.tubular(q))
                continue;
            layer[in_layer++] = q;
        }
        double total = 0, sum = 0, squares = 0, scattered = 0;
        for (std::size_t i = 0; i < in_layer; ++i) {
            const std::uint32_t q = layer[i];
            const Vec& m = planes.centroid[q];
            const double along = dot(n, Vec{m[0] - c[0], m[1] - c[1], m[2] - c[2]});
            const double w = static_cast<double>(planes.count[q]);
            total += w, sum += w * along, squares += w * along * along;
            scattered += along_normal(q, n);
        }
        const double mean = sum / total;
        spread[p] = std::max(0.0, (scattered + squares) / total - mean * mean);
        points[p] = total;
        middle[p] = mean;
    });
}

// Step 1c: a plate scanned on both faces, thinner than a cell, puts both faces' points in one
// layer of cells, and the sheet would run between them. Its layer's points spread along the
// normal by the scan's noise and the plate together: two faces d apart, each seen with noise of
// variance s^2, spread s^2 + d^2 / 4 about their middle (equal shares of points). The noise s^2
// is the median spread of the layers (most of a scan is surfaces seen from one side); a plane
// whose neighbours' layers (3 x 3 x 3, parallel, no tubes: their median, so that an edge or a
// corner among them does not count) spread at least twice that, and whose neighbours spread
// across its plane both ways over half a cell (a rail's cells lie along a line), holds two faces
// d / 2 = sqrt(spread - s^2) either side of it: at most half a cell (thicker, the faces are cells
// apart and the sheet already has both), at least a tenth (closer, the outputs' quantization, a
// tenth of a cell, would not keep them apart; and a scan without noise has no spread to compare
// with). The spread is a second moment: the faces' shares, and whether the points are two faces
// or one noisier surface, are not told apart; only that the spread is more than the scan's noise
// elsewhere explains.
constexpr double two_faces_spread = 2;
// A plate's neighbours spread across its plane in both directions, a rail's along one: the
// neighbours' mean squared offset along the plane's narrower direction (the smaller eigenvalue of
// their in-plane spread) is at least this many cells squared. Measured on a floor, a 3 cm plate
// and a 5 cm rail at 6.5 cm cells with 1 cm of noise: the plate's cells 0.45 (5th percentile) to
// 0.65 (median), the rail's 0.10 to 0.19 (75th percentile).
constexpr double plate_min_width = 0.3;
// Layers of fewer points give too loose a spread to judge by.
constexpr double layer_min_points = 8;

// The scan's noise s^2: the median of the spreads of the layers of layer_min_points or more (0
// with fewer than 16 of them: too few to tell the noise from the surfaces).
double median_spread(std::vector<double> usable) {
    if (usable.size() < 16) return 0;
    const auto half_way = usable.begin() + static_cast<std::ptrdiff_t>(usable.size() / 2);
    std::nth_element(usable.begin(), half_way, usable.end());
    return *half_way;
}

// The spreads of the layers of layer_min_points or more, of the planes `keep` takes.
template <class Keep>
std::vector<double> usable_spreads(const std::vector<double>& spread, const std::vector<double>& points, Keep keep) {
    std::vector<double> usable;
    for (std::size_t p = 0; p < spread.size(); ++p)
        if (points[p] >= layer_min_points && keep(p)) usable.push_back(spread[p]);
    return usable;
}

double layer_noise(const std::vector<double>& spread, const std::vector<double>& points) {
    return median_spread(usable_spreads(spread, points, [](std::size_t) { return true; }));
}

void estimate_thickness(Planes& planes, double h, const std::vector<double>& spread, const std::vector<double>& points,
                        const std::vector<double>& middle, double noise) {
    const std::size_t n = planes.cell.size();
    // A cell more than 16 times the noise across holds more of the surfaces' shape than of their
    // noise: its layers gather other surfaces along the normal, and a plate a tenth of a cell
    // thick is many times the noise (the generated deck's walls were found at 6 and 12 cm cells,
    // and at 25 and 50 cm only layers that met other surfaces were).
    if (!(noise > 0) || h > 16 * std::sqrt(noise)) return;
    std::vector<float> half(n, 0);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t p) {
        if (points[p] < layer_min_points) return;
        const Vec& normal = planes.normal[p];
        const Vec& c = planes.centroid[p];
        // Two axes in the plane, to tell a plate's neighbours (spread both ways) from a rail's (a
        // line of cells whose planes do not follow it).
        const Vec u = std::abs(normal[0]) < 0.9 ? Vec{0, -normal[2], normal[1]} : Vec{-normal[2], 0, normal[0]};
        const double u_length = std::sqrt(dot(u, u));
        const Vec e1{u[0] / u_length, u[1] / u_length, u[2] / u_length};
        const Vec e2{normal[1] * e1[2] - normal[2] * e1[1], normal[2] * e1[0] - normal[0] * e1[2],
                     normal[0] * e1[1] - normal[1] * e1[0]};
        std::array<double, 27> near;
        std::size_t count = 0;
        double s11 = 0, s22 = 0, s12 = 0;
        planes.for_each_within(static_cast<std::uint32_t>(p), 1, [&](std::uint32_t q) {
            if (points[q] < layer_min_points || std::abs(dot(normal, planes.normal[q])) < 0.9) return;
            near[count++] = spread[q];
            const Vec& m = planes.centroid[q];
            const Vec d{m[0] - c[0], m[1] - c[1], m[2] - c[2]};
            const double a = dot(d, e1), b = dot(d, e2);
            s11 += a * a, s22 += b * b, s12 += a * b;
        });
        if (count < 5) return;
        // The in-plane spread's smaller eigenvalue (2 x 2: closed form).
        const double mean = 0.5 * (s11 + s22), gap = std::sqrt(0.25 * (s11 - s22) * (s11 - s22) + s12 * s12);
        if (mean - gap < plate_min_width * h * h * static_cast<double>(count)) return;
        std::nth_element(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(count / 2),
                         near.begin() + static_cast<std::ptrdiff_t>(count));
        const double median = near[count / 2];
        if (median < two_faces_spread * noise) return;
        const double d = std::sqrt(median - noise);
        if (d >= 0.1 * h && d <= 0.5 * h) half[p] = static_cast<float>(d);
    });
    if (std::none_of(half.begin(), half.end(), [](float d) { return d > 0; })) return;
    // A plate's planes go to the middle of its points (their layer's mean): the band of points
    // across both faces spans cells whose own centroids lie each nearer one face.
    for (std::size_t p = 0; p < n; ++p)
        if (half[p] > 0)
            for (int a = 0; a < 3; ++a) planes.centroid[p][a] += middle[p] * planes.normal[p][a];
    planes.half_thickness = std::move(half);
}

// Whether q lies along p's plane rather than across it: the step between their centroids makes
// an angle under 30 degrees with the plane. Cells across a wall (the wall's other face) do not.
bool along_plane(const Planes& planes, std::uint32_t p, std::uint32_t q) {
    const Vec& a = planes.centroid[p];
    const Vec& b = planes.centroid[q];
    const Vec step{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double across = std::abs(dot(planes.normal[p], step));
    return across <= 0.5 * std::sqrt(dot(step, step));
}

// A plane whose normal is within 45 degrees of a tube's axis lies across the tube.
constexpr double across_tube_cosine = 0.7071;
// The spread of a tube's cells' centroids across its axis is round: the smaller of its two
// across is at least this share of the larger. Centroids on a circle give a half to one; a strip
// along a plane's edge, two or three cells wide and as thick as the scan's noise, about a sixth
// (1 cm of noise at 3 cm cells), and was taken for a tube at a tenth.
constexpr double round_across = 0.3;

// Step 1b (LinearParts::tubes): a surface cell whose surface cells around it (5 x 5 x 5, at least
// four) lie along a line gets a tube round that line: the axis through their count-weighted mean
// along their principal axis, the radius their RMS distance from it. Along a line: the spread of
// their centroids (the covariance's eigenvalues, largest first) is long (the second under half the
// first) and round across it (the third over round_across of the second: a strip of a plane's
// edge is long but flat), or too narrow to tell (the second under a quarter of a cell squared: a rail
// thinner than the lattice). The radius is at most two cells. A cell's centroid is the centroid of
// the arc of the tube's surface inside it, about a cell long, which lies sin(t) / t of the radius
// from the axis (t half the arc's angle, h / 2R): the radius is corrected by that, and raised to
// sqrt(2) / 2 of a cell, the distance from a line through cell centres along a lattice axis to the
// nearest lattice edge: a thinner tube would slip between the corners and vanish.
void estimate_tubes(Planes& planes) {
    const std::size_t n = planes.cell.size();
    planes.tube.assign(n, Tube{});
    const double h = planes.grid.spec.cell_size;
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t p) {
        std::array<std::uint32_t, 125> near;
        std::size_t count = 0;
        planes.for_each_within(static_cast<std::uint32_t>(p), 2, [&](std::uint32_t q) { near[count++] = q; });
        if (count < 4) return;
        double total = 0;
        Vec mean{};
        for (std::size_t k = 0; k < count; ++k) {
            const double w = static_cast<double>(planes.count[near[k]]);
            total += w;
            for (int i = 0; i < 3; ++i) mean[i] += w * planes.centroid[near[k]][i];
        }
        for (double& m : mean) m /= total;
        std::array<std::array<double, 3>, 3> covariance{}, negated{};
        for (std::size_t k = 0; k < count; ++k) {
            const double w = static_cast<double>(planes.count[near[k]]);
            const Vec& q = planes.centroid[near[k]];
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) covariance[i][j] += w * (q[i] - mean[i]) * (q[j] - mean[j]);
        }
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) negated[i][j] = -covariance[i][j];
        const Vec direction = plane_normal(negated); // the smallest eigenvector of -C: C's largest
        const std::array<double, 3> spread = symmetric_eigenvalues(covariance); // largest first
        // The count-weighted squared distances from the axis: the spread across it.
        const double across = spread[1] + spread[2];
        const bool long_and_round =
            spread[1] < 0.5 * spread[0] && (spread[2] > round_across * spread[1] || spread[1] < 0.25 * h * h * total);
        if (!long_and_round || across > 4 * h * h * total) return;
        const double rms = std::sqrt(across / total);
        double radius = rms;
        for (int k = 0; k < 3; ++k) {
            const double t = std::min(h / radius, 3.0) / 2;
            radius = rms * t / std::sin(t);
        }
        planes.tube[p] = {mean, direction, std::max(radius, std::numbers::sqrt2 / 2 * h)};
    });
    // The cells that are no tube but lie on or in tubes around them (their centroid inside a tube
    // of the 5 x 5 x 5 cells, or within half a cell of its surface): where a rail meets a post the
    // cells' spread is two lines, not one, and a tube's last cells are not along a line either.
    // They take the union of those tubes (the nearest of them at each corner), up to four running
    // different ways (over 30 degrees apart), nearest first; as planes, their crossings with the
    // tubes would be refused and the junction left open.
    planes.joins.assign(n, {no_plane, no_plane, no_plane, no_plane});
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t p) {
        if (planes.tube[p].radius > 0) return;
        // The plane of the cell's own points where the grid has their moments and they are flat
        // (the cells around lean toward a dense tube next to it), else its neighbourhood's: a
        // few points, or points along a line, have no plane of their own.
        Vec own = planes.normal[p];
        if (!planes.scatter.empty() && planes.count[p] >= 3) {
            const std::array<float, 6>& m = planes.scatter[p];
            const std::array<std::array<double, 3>, 3> scatter{
                {{m[0], m[3], m[4]}, {m[3], m[1], m[5]}, {m[4], m[5], m[2]}}};
            const std::array<double, 3> e = symmetric_eigenvalues(scatter); // largest first
            if (e[2] < 0.25 * e[1]) own = plane_normal(scatter);
        }
        std::array<std::pair<double, std::uint32_t>, 125> on;
        std::size_t count = 0;
        planes.for_each_within(static_cast<std::uint32_t>(p), 2, [&](std::uint32_t q) {
            if (!(planes.tube[q].radius > 0)) return;
            // A plane across the tube's axis is a surface the tube stands on or runs into (the
            // deck under a post, a wall a pipe enters), not part of the tube: it stays a plane.
            if (std::abs(dot(own, planes.tube[q].direction)) > across_tube_cosine) return;
            const double off = surface_distance(planes.tube[q], planes.centroid[p]);
            if (off <= h / 2) on[count++] = {std::abs(off), q};
        });
        std::sort(on.begin(), on.begin() + static_cast<std::ptrdiff_t>(count));
        std::size_t taken = 0;
        for (std::size_t k = 0; k < count && taken < 4; ++k) {
            const Vec& d = planes.tube[on[k].second].direction;
            bool apart = true;
            for (std::size_t j = 0; j < taken; ++j)
                apart = apart && std::abs(dot(d, planes.tube[planes.joins[p][j]].direction)) < 0.866;
            if (apart) planes.joins[p][taken++] = on[k].second;
        }
    });
}

// Whether q continues the plate p is on: its normal within 14 degrees of p's. A plate (its
// two-faced planes and their neighbours along it) is one sheet for two faces, so the orientation
// it hands on holds only within it: the floor on its far side (a deckhouse's floor inside,
// reached from the deck outside over a wall) is no continuation of the face the sheet's normal
// points from. A plate's foot turns to a floor over a cell or two, each step gentle enough to
// pass for one smooth surface (smooth_cosine), hence the stricter angle.
bool in_plate(const Planes& planes, std::uint32_t p, std::uint32_t q) {
    return std::abs(dot(planes.normal[p], planes.normal[q])) >= 0.97;
}

// Whether a neighbour of p is a plate's plane.
bool next_to_plate(const Planes& planes, std::uint32_t p) {
    bool near = false;
    planes.for_each_neighbour(p, [&](std::uint32_t q) { near = near || planes.two_faced(q); });
    return near;
}

// A piece faces the way the outside says when the point counts of its planes that see it one
// way, less the other, are at least this share of its points.
constexpr double outside_min_share = 0.01;

// Neighbouring planes closer to parallel than this (the cosine of 25 degrees) continue one smooth
// surface; at a box's edge (90 degrees) the cells' planes turn in steps of about 45.
constexpr double smooth_cosine = 0.9;

// Step 2: consistent orientation by a maximum spanning tree (Prim, bucketed weights |n_p . n_q|),
// grown from the first plane of each connected piece (Hoppe et al., "Surface reconstruction from
// unorganized points", 1992): neighbours must agree, or the extraction leaves a crack where they
// meet. A plane whose neighbourhood sees the outside on one side only (`outside_side`, from
// OutsideSpace: a box's wall, a roof, a deck) joins a piece only facing the way the piece's first such
// plane does: a box's wall reached from a floor inside the box (as on decks scanned under their
// containers) starts a piece of its own instead of turning inward. A plate's planes (two faces in
// one sheet) hand their orientation on only within the plate (in_plate), so the floors on its
// two sides are oriented each on its own. Then each piece faces the way most of its planes that
// see a side say, by their point counts, when they are outside_min_share of it; else outward
// when it encloses something (its normals point away from its centroid on the whole: a
// sphere), else up (a room's floor inside, which no outside sees).
void orient_normals(Planes& planes, const OutsideSpace& outside) {
    const std::size_t n = planes.cell.size();
    const double h = planes.grid.spec.cell_size;
    // Which side of each plane is outside: +1 its normal's, -1 the other, 0 both or neither; then
    // the same by its 3 x 3 x 3 neighbourhood's count-weighted majority (a stray plane's own view
    // would start a piece and leave a crack around it).
    std::vector<std::int8_t> own(n, 0), seen(n, 0);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t p) {
        const Vec& normal = planes.normal[p];
        const bool front = outside.open(planes.centroid[p], normal, h);
        const bool back = outside.open(planes.centroid[p], Vec{-normal[0], -normal[1], -normal[2]}, h);
        own[p] = front == back ? 0 : front ? 1 : -1;
    });
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t p) {
        double sum = static_cast<double>(own[p]) * static_cast<double>(planes.count[p]);
        planes.for_each_neighbour(std::uint32_t(p), [&](std::uint32_t q) {
            const double along = dot(planes.normal[p], planes.normal[q]);
            if (std::abs(along) > 0.5) sum += (along < 0 ? -own[q] : own[q]) * static_cast<double>(planes.count[q]);
        });
        seen[p] = sum > 0 ? 1 : sum < 0 ? -1 : 0;
    });
    constexpr int levels = 16;
    std::vector<std::int8_t> best(n, -1);
    std::vector<std::uint32_t> parent(n, no_plane);
    std::vector<char> plate(n, 0); // a plate's plane, or reached along it from one and next to one
    std::vector<bool> done(n, false);
    std::array<std::vector<std::uint32_t>, levels + 1> buckets;
    std::vector<std::uint32_t> piece;
    for (std::uint32_t seed = 0; seed < n; ++seed) {
        if (done[seed]) continue;
        piece.clear();
        parent[seed] = seed;
        buckets[levels].push_back(seed);
        double votes = 0; // point counts of the planes whose outside is their normal's side now, less the others'
        std::int8_t outside_side = 0; // that side, as the piece's first plane to see one saw it
        for (int level = levels; level >= 0;) {
            if (buckets[level].empty()) {
                --level;
                continue;
            }
            const std::uint32_t p = buckets[level].back();
            buckets[level].pop_back();
            if (done[p]) continue;
            Vec& np = planes.normal[p];
            const double along = parent[p] != p ? dot(np, planes.normal[parent[p]]) : 1.0;
            const bool turn = along < 0;
            const std::int8_t side = static_cast<std::int8_t>(turn ? -seen[p] : seen[p]);
            // Parted only round an edge: along a smooth surface a crack would cost more.
            if (side != 0 && outside_side != 0 && side != outside_side && std::abs(along) < smooth_cosine) {
                best[p] = -1; // another neighbour may take it, or it starts a piece
                continue;
            }
            done[p] = true;
            plate[p] = planes.two_faced(p) || (parent[p] != p && plate[parent[p]] && next_to_plate(planes, p));
            piece.push_back(p);
            if (turn) np = {-np[0], -np[1], -np[2]};
            seen[p] = side;
            if (side != 0 && outside_side == 0) outside_side = side;
            votes += static_cast<double>(side) * static_cast<double>(planes.count[p]);
            planes.for_each_neighbour(p, [&](std::uint32_t q) {
                if (done[q] || !along_plane(planes, p, q) || !along_plane(planes, q, p)) return;
                if (plate[p] && !planes.two_faced(q) && !in_plate(planes, p, q)) return;
                const auto w = static_cast<std::int8_t>(std::lround(std::abs(dot(np, planes.normal[q])) * levels));
                if (w <= best[q]) return;
                best[q] = w;
                parent[q] = p;
                buckets[w].push_back(q);
                level = std::max<int>(level, w);
            });
        }
        // Outward: the normals' count-weighted agreement with the directions from the piece's
        // centroid, against the whole weight; a flat or open piece scores near 0.
        Vec centre{};
        double weight = 0;
        for (std::uint32_t p : piece) {
            const double w = static_cast<double>(planes.count[p]);
            for (int a = 0; a < 3; ++a) centre[a] += w * planes.centroid[p][a];
            weight += w;
        }
        for (double& c : centre) c /= weight;
        double outward = 0, up = 0;
        for (std::uint32_t p : piece) {
            const double w = static_cast<double>(planes.count[p]);
            const Vec& c = planes.centroid[p];
            const Vec away{c[0] - centre[0], c[1] - centre[1], c[2] - centre[2]};
            const double length = std::sqrt(dot(away, away));
            if (length > 0) outward += w * dot(planes.normal[p], away) / length;
            up += w * planes.normal[p][2];
        }
        const bool encloses = std::abs(outward) > 0.5 * weight;
        // A few stray planes' view (one seeing past a plate's foot) does not turn a whole floor.
        const bool decided = std::abs(votes) >= outside_min_share * weight;
        if (decided ? votes < 0 : encloses ? outward < 0 : up < 0)
            for (std::uint32_t p : piece)
                planes.normal[p] = {-planes.normal[p][0], -planes.normal[p][1], -planes.normal[p][2]};
    }
}

// Step 5: each connected part of the mesh faces the outside. The sheets of surfaces that meet at a
// sharp edge (a deck and a box's walls, the walls and the roof) are separate parts, so each can
// turn on its own, and no part is split. A part turns (winding and normals) when the area of its
// triangles with the outside behind them and not in front exceeds the area with it in front and
// not behind: a box's wall reached by the spanning tree from the floor inside the box.
void face_outside(Mesh& mesh, const OutsideSpace& outside, double cell) {
    const std::vector<std::uint32_t> part = connected_parts(mesh);
    const std::vector<double> triangle_votes = outside_votes(mesh, outside, cell);
    std::vector<double> votes(mesh.positions.size(), 0); // per part
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) votes[part[mesh.triangles[i][0]]] += triangle_votes[i];
    std::vector<char> turn(mesh.positions.size(), 0);
    for (std::uint32_t v = 0; v < turn.size(); ++v) turn[v] = votes[part[v]] < 0;
    turn_over(mesh, turn);
}

// How far past its points' end, in cells, a sheet may run into cells without points
// (SheetField::past_points). On the generated decks: at 20M points a quarter, a half and a whole
// cell gave the same error (0.333-0.334 cm) and a tenth 9% more triangles; at 2M points a half
// cell gave the least error and the fewest triangles (0.556 cm, 56,913; a whole cell 0.579 cm).
constexpr double sheet_end_margin = 0.5;

// Steps 3 and 4: the signed distance at the cell corners, as a field for sparse marching cubes.
// Lattice point (x, y, z) is the corner at (x, y, z) cells from the grid origin.
struct SheetField {
    const Planes& planes;
    std::array<std::int64_t, 3> points;
    double h;
    // A corner is defined only within two cells of a plane (the cells it looks at below run from
    // two below it to one above), so with the lattice `extract` marches (the bricks of corners a
    // cell below to two above every surface brick's cells) no corner outside it is defined.
    static constexpr bool undefined_outside_active = true;
    // Where this sheet meets a coarser one's mesh: the faces on which it takes the coarser
    // sheet's values.
    const SeamFaces* seam = nullptr;

    // Whether `corner` lies along p's plane more than sheet_end_margin cells past where p's
    // points end, the way to it: their mean plus sqrt(3) standard deviations that way (the end
    // of an even spread). A corner defined from the ring of cells around it (no cell next to it
    // has a plane) that lies past the points of every one of those cells is left undefined, so
    // the sheet ends in or at its last cells instead of running a cell on past the points (a
    // deck's edge, a pipe's open end, a fin around a rail thinner than a cell). Where the zero
    // set leaves a surface cell into an empty one and returns (a plane at a slant to the
    // lattice), the corners it needs lie within the spread of the cells around; where the
    // surface curves round within the ring (a pipe a cell or two across, meshed in pieces that
    // such corners join), the ring's planes turn more than 25 degrees and the corner stays.
    bool past_points(std::uint32_t p, const Vec& corner) const {
        if (planes.spread_along.empty() || planes.tubular(p)) return false;
        const Vec& m = planes.centroid[p];
        const Vec& n = planes.normal[p];
        const Vec d{corner[0] - m[0], corner[1] - m[1], corner[2] - m[2]};
        const std::array<Vec, 2> t = along_plane_axes(n);
        const double u = dot(d, t[0]), v = dot(d, t[1]), along = std::sqrt(u * u + v * v);
        if (!(along > 0)) return false;
        const std::array<float, 3>& c = planes.spread_along[p];
        const double variance = (u * u * c[0] + v * v * c[1] + 2 * u * v * c[2]) / (along * along);
        return along > std::sqrt(3 * std::max(0.0, variance)) + sheet_end_margin * h;
    }

    // The samples of a block of n^3 corners from `first`, with the planes of the cells they
    // look at (two cells beyond the block each way) looked up once.
    struct Sampler {
        const SheetField& field;
        std::array<std::int64_t, 3> first; // the first cell held
        std::int64_t span;                 // cells held per axis
        std::vector<std::uint32_t> plane;  // per held cell, x fastest
        std::vector<std::uint16_t> row;    // per held row (y, z): bit x set where a plane is
        bool empty = true;                 // no surface cell near the block: nothing defined

        std::uint32_t at(std::int64_t x, std::int64_t y, std::int64_t z) const {
            return plane[((z - first[2]) * span + (y - first[1])) * span + (x - first[0])];
        }
        detail::FieldSample sample(std::int64_t x, std::int64_t y, std::int64_t z) const {
            const auto& points = field.points;
            if (empty || x < 0 || y < 0 || z < 0 || x >= points[0] || y >= points[1] || z >= points[2]) return {};
            const double h = field.h;
            const Vec corner{static_cast<double>(x) * h, static_cast<double>(y) * h, static_cast<double>(z) * h};
            const Planes& planes = field.planes;
            std::uint32_t nearest = no_plane;
            double nearest_distance = 0;
            // The corner from the ring; past every ring cell's points; their planes alike (within
            // 25 degrees of the first's: one surface running out, not one curving round).
            bool from_ring = false, past_all = true;
            std::uint32_t first_ring = no_plane;
            auto consider = [&](std::int64_t cx, std::int64_t cy, std::int64_t cz) {
                const std::uint32_t p = at(cx, cy, cz);
                if (p == no_plane) return;
                if (from_ring && past_all) {
                    if (first_ring == no_plane) first_ring = p;
                    past_all = std::abs(dot(planes.normal[p], planes.normal[first_ring])) >= smooth_cosine &&
                               field.past_points(p, corner);
                }
                const Vec& m = planes.centroid[p];
                const Vec d{corner[0] - m[0], corner[1] - m[1], corner[2] - m[2]};
                if (nearest == no_plane || dot(d, d) < nearest_distance) nearest = p, nearest_distance = dot(d, d);
            };
            // The eight cells around the corner, in a fixed order; failing those, the ring of
            // cells around them, so that every cube next to a surface cell has all its corners:
            // the zero set may leave a surface cell through a face into an empty one.
            for (int c = 0; c < 8; ++c) consider(x - 1 + (c & 1), y - 1 + ((c >> 1) & 1), z - 1 + ((c >> 2) & 1));
            from_ring = nearest == no_plane;
            if (nearest == no_plane)
                for (std::int64_t cz = z - 2; cz <= z + 1; ++cz)
                    for (std::int64_t cy = y - 2; cy <= y + 1; ++cy)
                        // Only the cells with a plane, in the same order (x rising).
                        for (unsigned bits = (row[static_cast<std::size_t>((cz - first[2]) * span + (cy - first[1]))] >>
                                              (x - 2 - first[0])) &
                                             0xFu;
                             bits != 0; bits &= bits - 1)
                            consider(x - 2 + std::countr_zero(bits), cy, cz);
            if (nearest == no_plane || (from_ring && past_all)) return {};
            if (field.seam) {
                float coarse = 0;
                const Vec n = field.normal_at(nearest, corner);
                switch (field.seam->coarse_value(x, y, z, n, coarse)) {
                case SeamFaces::Found::undefined: return {};
                case SeamFaces::Found::value: return {coarse, nearest, true, coarse < 0};
                case SeamFaces::Found::off_seam: break;
                }
            }
            if (const auto [f, tube] = planes.tube_distance(nearest, corner); tube) // to the tube, out
                return {static_cast<float>(f), nearest, true, f < 0};
            const Vec& m = planes.centroid[nearest];
            const double f = dot(planes.normal[nearest], Vec{corner[0] - m[0], corner[1] - m[1], corner[2] - m[2]});
            return {static_cast<float>(f), nearest, true, f < 0};
        }
    };
    Sampler sampler(const std::array<std::int64_t, 3>& first_corner, std::int64_t n) const {
        Sampler s{*this, {first_corner[0] - 2, first_corner[1] - 2, first_corner[2] - 2}, n + 3, {}, {}};
        s.plane.assign(static_cast<std::size_t>(s.span * s.span * s.span), no_plane);
        s.row.assign(static_cast<std::size_t>(s.span * s.span), 0);
        assert(s.span <= 16);
        // Copied from the grid's bricks that overlap the held cells: one index lookup a brick.
        const CellGrid& g = planes.grid;
        constexpr int bits = CellGrid::brick_bits;
        constexpr std::int64_t size = CellGrid::brick_size;
        std::array<std::int64_t, 3> lo{}, hi{};
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max<std::int64_t>(s.first[a] >> bits, 0);
            hi[a] = std::min<std::int64_t>((s.first[a] + s.span - 1) >> bits, std::int64_t{g.bricks[a]} - 1);
        }
        for (std::int64_t bz = lo[2]; bz <= hi[2]; ++bz)
            for (std::int64_t by = lo[1]; by <= hi[1]; ++by)
                for (std::int64_t bx = lo[0]; bx <= hi[0]; ++bx) {
                    const std::uint32_t at = g.brick_table.find(
                        (std::uint64_t(bz) * g.bricks[1] + std::uint64_t(by)) * g.bricks[0] + std::uint64_t(bx));
                    if (at == 0) continue;
                    // The brick's planes by cell (its records hold only the occupied cells).
                    std::array<std::uint32_t, CellGrid::brick_cells> records;
                    records.fill(no_plane);
                    std::uint64_t r = g.brick_first[at - 1];
                    for (std::uint64_t mask = g.brick_masks[at - 1]; mask != 0; mask &= mask - 1)
                        records[static_cast<std::size_t>(std::countr_zero(mask))] = planes.of_record[r++];
                    for (std::int64_t z = std::max(bz * size, s.first[2]);
                         z < std::min((bz + 1) * size, s.first[2] + s.span); ++z)
                        for (std::int64_t y = std::max(by * size, s.first[1]);
                             y < std::min((by + 1) * size, s.first[1] + s.span); ++y)
                            for (std::int64_t x = std::max(bx * size, s.first[0]);
                                 x < std::min((bx + 1) * size, s.first[0] + s.span); ++x) {
                                const std::uint32_t p = records[static_cast<std::size_t>(
                                    ((z - bz * size) * size + (y - by * size)) * size + (x - bx * size))];
                                if (p == no_plane) continue;
                                const std::size_t row =
                                    static_cast<std::size_t>((z - s.first[2]) * s.span + (y - s.first[1]));
                                s.plane[row * static_cast<std::size_t>(s.span) +
                                        static_cast<std::size_t>(x - s.first[0])] = p;
                                s.row[row] = static_cast<std::uint16_t>(s.row[row] | 1u << (x - s.first[0]));
                                s.empty = false;
                            }
                }
        return s;
    }

    // Two planes are the same surface when their normals point to the same side and each
    // centroid lies within two cells of the other's plane (measured on the deck: stricter
    // rules tear more holes than they avoid stray triangles).
    bool accepts(const detail::FieldSample& a, const detail::FieldSample& b) const {
        if (a.source == b.source) return true;
        // Tubes meet tubes (their distances are both outward), not planes.
        if (planes.tubular(a.source) || planes.tubular(b.source))
            return planes.tubular(a.source) && planes.tubular(b.source);
        const Vec& na = planes.normal[a.source];
        const Vec& nb = planes.normal[b.source];
        if (dot(na, nb) <= 0) return false;
        const Vec& pa = planes.centroid[a.source];
        const Vec& pb = planes.centroid[b.source];
        const Vec d{pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
        return std::abs(dot(na, d)) <= 2 * h && std::abs(dot(nb, d)) <= 2 * h;
    }
    // The surface's normal at `at` as cell p's plane or tube has it: a tube's points away from its axis.
    Vec normal_at(std::uint32_t p, const Vec& at) const {
        const Tube* nearest = planes.tube_distance(p, at).second;
        if (!nearest) return planes.normal[p];
        const Tube& tube = *nearest;
        const Vec r{at[0] - tube.point[0], at[1] - tube.point[1], at[2] - tube.point[2]};
        const double along = dot(r, tube.direction);
        const Vec out{r[0] - along * tube.direction[0], r[1] - along * tube.direction[1],
                      r[2] - along * tube.direction[2]};
        const double length = std::sqrt(dot(out, out));
        return length > 0 ? Vec{out[0] / length, out[1] / length, out[2] / length} : planes.normal[p];
    }
    void vertex(const std::array<std::int64_t, 3>& p, int axis, const detail::FieldSample& a,
                const detail::FieldSample& b, detail::VertexOut& out) const {
        // Linear interpolation puts the vertex on the plane when both corners share it; kept a
        // tenth of the edge from either corner, so that no triangle shrinks below what the
        // outputs' quantization (a tenth of a cell by default) keeps apart.
        const double t = std::clamp(static_cast<double>(a.value) / (static_cast<double>(a.value) - b.value), 0.1, 0.9);
        for (int c = 0; c < 3; ++c)
            out.position[c] = static_cast<float>((static_cast<double>(p[c]) + (c == axis ? t : 0.0)) * h);
        const Vec at{out.position[0], out.position[1], out.position[2]};
        const Vec na = normal_at(a.source, at), nb = normal_at(b.source, at);
        Vec n{(1 - t) * na[0] + t * nb[0], (1 - t) * na[1] + t * nb[1], (1 - t) * na[2] + t * nb[2]};
        const double length = std::sqrt(dot(n, n));
        for (int c = 0; c < 3; ++c) out.normal[c] = static_cast<float>(length > 0 ? n[c] / length : na[c]);
        if (!planes.color.empty()) {
            const Rgb8& ca = planes.color[a.source];
            const Rgb8& cb = planes.color[b.source];
            for (int c = 0; c < 3; ++c)
                out.color[c] = static_cast<std::uint8_t>(std::lround((1 - t) * ca[c] + t * cb[c]));
        }
        if (!planes.half_thickness.empty())
            out.offset =
                static_cast<float>((1 - t) * planes.half_thickness[a.source] + t * planes.half_thickness[b.source]);
    }
};

} // namespace

// Step 6: where a plate has two faces (estimate_thickness), its sheet becomes two: every triangle
// with a corner on a plate is copied, the copy turned over and each moved half the plate's
// thickness along its normals, out to the side it faces. The vertices of such triangles where the
// plate ends (half thickness 0) stay where they are: the front face shares them with the sheet it
// continues, the back face has its own, so the back face is an open sheet of its own and no edge
// gets three triangles.
void split_two_faces(Mesh& mesh, const std::vector<float>& half) {
    const std::size_t nv = mesh.positions.size(), nt = mesh.triangles.size();
    std::vector<std::uint32_t> back(nv, UINT32_MAX);
    const bool colored = !mesh.colors.empty();
    for (std::size_t t = 0; t < nt; ++t) {
        auto tri = mesh.triangles[t];
        if (!(half[tri[0]] > 0 || half[tri[1]] > 0 || half[tri[2]] > 0)) continue;
        for (auto& v : tri) {
            if (back[v] == UINT32_MAX) {
                back[v] = static_cast<std::uint32_t>(mesh.positions.size());
                const auto n = mesh.normals[v]; // copies: the vectors grow below
                const auto p = mesh.positions[v];
                mesh.positions.push_back({p[0] - half[v] * n[0], p[1] - half[v] * n[1], p[2] - half[v] * n[2]});
                mesh.normals.push_back({-n[0], -n[1], -n[2]});
                if (colored) mesh.colors.push_back(mesh.colors[v]);
            }
            v = back[v];
        }
        mesh.triangles.push_back({tri[0], tri[2], tri[1]});
    }
    for (std::size_t v = 0; v < nv; ++v) {
        const auto& n = mesh.normals[v];
        for (int c = 0; c < 3; ++c) mesh.positions[v][c] += half[v] * n[c];
    }
}

namespace {

// Each plane's points' covariance along its plane, from its cell's scatter (sum (p - c)(p - c)^T:
// xx, yy, zz, xy, xz, yz) over its count.
void keep_spread_along(Planes& planes) {
    planes.spread_along.resize(planes.scatter.size());
    tbb::parallel_for(std::size_t{0}, planes.scatter.size(), [&](std::size_t p) {
        const std::array<float, 6>& m = planes.scatter[p];
        const std::array<std::array<double, 3>, 3> s{{{m[0], m[3], m[4]}, {m[3], m[1], m[5]}, {m[4], m[5], m[2]}}};
        const std::array<Vec, 2> t = along_plane_axes(planes.normal[p]);
        const auto product = [&](const Vec& a, const Vec& b) {
            double sum = 0;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) sum += a[i] * s[i][j] * b[j];
            return sum / static_cast<double>(planes.count[p]);
        };
        planes.spread_along[p] = {float(product(t[0], t[0])), float(product(t[1], t[1])), float(product(t[0], t[1]))};
    });
}

// The sheet's samples at the seam's corners, and the crossings it rejects on the lattice edges
// between them (SeamCorners).
void sample_seam(const SheetField& field, SeamCorners& c) {
    const std::size_t n = c.corners.size();
    std::vector<detail::FieldSample> sample(n);
    c.value.assign(n, 0);
    c.normal.assign(n, {});
    c.flags.assign(n, 0);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        const std::array<std::int64_t, 3> p = c.corner_of(c.corners[i]);
        const detail::FieldSample s = field.sampler(p, 1).sample(p[0], p[1], p[2]);
        sample[i] = s;
        if (!s.defined) return;
        c.value[i] = s.value;
        const double h = field.h;
        const Vec n = field.normal_at(s.source, Vec{double(p[0]) * h, double(p[1]) * h, double(p[2]) * h});
        c.normal[i] = {float(n[0]), float(n[1]), float(n[2])};
        c.flags[i] = SeamCorners::defined;
    });
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
        if (!sample[i].defined) return;
        const std::array<std::int64_t, 3> p = c.corner_of(c.corners[i]);
        for (int a = 0; a < 3; ++a) {
            std::array<std::int64_t, 3> q = p;
            ++q[a];
            const std::uint64_t key = c.key_of(q[0], q[1], q[2]);
            const auto at = std::lower_bound(c.corners.begin(), c.corners.end(), key);
            if (at == c.corners.end() || *at != key) continue;
            const detail::FieldSample& s = sample[i];
            const detail::FieldSample& t = sample[static_cast<std::size_t>(at - c.corners.begin())];
            if (t.defined && s.inside != t.inside && !field.accepts(s, t))
                c.flags[i] = static_cast<std::uint8_t>(c.flags[i] | 1u << (1 + a));
        }
    });
}

// `owned`, when given, is `grid` itself, ours to empty as we go (the grid and the planes are most
// of the memory at fine grids): its cells once the planes hold what is needed of them, its brick
// table once the corners are sampled.
// Step 1 after the planes are made: their normals, tubes, plates and places (all but facing).
// `survey` gives the scan's noise, else the planes' own.
void shape_planes(Planes& planes, LinearParts linear, const SheetSurvey* survey) {
    const double h = planes.grid.spec.cell_size;
    estimate_normals(planes);
    if (linear == LinearParts::tubes) estimate_tubes(planes);
    if (!planes.scatter.empty()) {
        {
            std::vector<double> spread, points, middle;
            layer_spreads(planes, h, spread, points, middle);
            estimate_thickness(planes, h, spread, points, middle, survey ? survey->noise : layer_noise(spread, points));
        }
        keep_spread_along(planes);
        std::vector<std::array<float, 6>>().swap(planes.scatter);
    }
    pool_split_layers(planes, h);
}

// Turns the planes `facing` names.
void face_planes(Planes& planes, const PlaneFacing& facing) {
    tbb::parallel_for(std::size_t{0}, planes.cell.size(), [&](std::size_t p) {
        if (std::binary_search(facing.turned.begin(), facing.turned.end(), planes.grid.order_key(planes.cell[p])))
            for (double& c : planes.normal[p]) c = -c;
    });
}

// `faced`, when given, faces the planes instead of step 2, and the sheet is returned before step 5
// and the plates' split, with each vertex's half thickness in `half`.
Mesh extract(const CellGrid& grid, double iso, LinearParts linear, CellGrid* owned,
             const std::function<void()>& released, SeamRequest* seam_request,
             const std::function<const SeamCorners&()>& coarse_seam, const SheetSurvey* survey,
             const PlaneFacing* faced = nullptr, std::vector<float>* faced_half = nullptr) {
    Planes planes(grid, iso);
    if (owned) std::vector<CellSums>().swap(owned->cells);
    if (released) released();
    shape_planes(planes, linear, survey);
    std::optional<OutsideSpace> own_outside;
    const OutsideSpace* outside = nullptr;
    if (faced)
        face_planes(planes, *faced);
    else {
        outside = survey && survey->outside ? survey->outside.get() : &own_outside.emplace(grid.spec.dims, planes.cell);
        orient_normals(planes, *outside);
    }
    // The cells' coordinates and counts served the normals only: their memory goes to marching.
    std::vector<std::array<std::int64_t, 3>>().swap(planes.cell);
    std::vector<std::uint64_t>().swap(planes.count);
    SheetField field{
        planes, {grid.spec.dims[0] + 1, grid.spec.dims[1] + 1, grid.spec.dims[2] + 1}, grid.spec.cell_size};
    if (seam_request) {
        sample_seam(field, seam_request->corners);
        if (seam_request->sampled) seam_request->sampled(std::move(seam_request->corners));
    }
    std::optional<SeamFaces> seam_faces;
    if (coarse_seam) field.seam = &seam_faces.emplace(coarse_seam());
    // Corners are sampled only near surface cells: the bricks that hold one, and their neighbours.
    std::vector<std::uint64_t> surface_bricks;
    for (std::uint64_t b = 0; b < grid.brick_keys.size(); ++b) {
        const auto first = planes.of_record.begin() + static_cast<std::ptrdiff_t>(grid.brick_first[b]);
        if (std::any_of(first, first + std::popcount(grid.brick_masks[b]),
                        [](std::uint32_t p) { return p != no_plane; }))
            surface_bricks.push_back(grid.brick_keys[b]);
    }
    // Once sampled, the corners no longer look at cells: what finds a cell's plane may go, and
    // the points' spreads.
    const auto sampled = [&] {
        std::vector<std::uint32_t>().swap(planes.of_record);
        std::vector<std::array<float, 3>>().swap(planes.spread_along);
        if (!owned) return;
        owned->brick_table = BrickTable();
        for (auto* v : {&owned->brick_keys, &owned->brick_masks, &owned->brick_first})
            std::vector<std::uint64_t>().swap(*v);
    };
    std::vector<float> half;
    Mesh mesh = detail::march_sparse(field, detail::lattice_near_bricks(grid, surface_bricks, field.points, 1),
                                     grid.has_color(), sampled, planes.half_thickness.empty() ? nullptr : &half);
    agree_normals_with_faces(mesh);
    mesh.origin = grid.spec.origin;
    mesh.cell_size = grid.spec.cell_size;
    if (faced) {
        *faced_half = std::move(half);
        return mesh;
    }
    face_outside(mesh, *outside, grid.spec.cell_size);
    if (!half.empty()) split_two_faces(mesh, half);
    return mesh;
}

} // namespace

Mesh extract_sheet(const CellGrid& grid, double iso, LinearParts linear,
                   const std::function<const SeamCorners&()>& coarse_seam) {
    return extract(grid, iso, linear, nullptr, {}, nullptr, coarse_seam, nullptr);
}

Mesh extract_sheet(CellGrid&& grid, double iso, LinearParts linear, const std::function<void()>& released,
                   SeamRequest* seam) {
    return extract(grid, iso, linear, &grid, released, seam, {}, nullptr);
}

SheetSurvey sheet_survey(const CellGrid& grid, double iso, LinearParts linear) {
    const GridSpec& spec = grid.spec;
    return combined_survey({sheet_survey_part(grid, iso, {0, spec.dims[0], 0, spec.dims[1]}, linear)}, spec.dims);
}

UnfacedPlanes unfaced_planes(const CellGrid& part, double iso, const SheetSurvey& survey,
                             const std::array<std::int64_t, 4>& window, LinearParts linear) {
    Planes planes(part, iso);
    shape_planes(planes, linear, &survey);
    UnfacedPlanes in;
    for (std::size_t p = 0; p < planes.cell.size(); ++p) {
        const auto& c = planes.cell[p];
        if (c[0] < window[0] || c[0] >= window[1] || c[1] < window[2] || c[1] >= window[3]) continue;
        in.key.push_back(part.order_key(c));
        in.centroid.push_back(planes.centroid[p]);
        in.normal.push_back(planes.normal[p]);
        in.count.push_back(planes.count[p]);
        if (!planes.half_thickness.empty()) in.half_thickness.push_back(planes.half_thickness[p]);
    }
    return in;
}

PlaneFacing plane_facing(std::vector<UnfacedPlanes> parts, const GridSpec& grid, const SheetSurvey& survey) {
    // The parts' planes in the grid's order: each part's are in order, so the parts are merged (a
    // heap of the parts' next planes) and each freed once taken in: the memory is the planes'
    // twice at most, with no order over them.
    std::size_t total = 0;
    bool plates = false;
    for (const UnfacedPlanes& part : parts) {
        total += part.key.size();
        plates = plates || !part.half_thickness.empty();
    }
    UnfacedPlanes all;
    all.centroid.reserve(total), all.normal.reserve(total), all.count.reserve(total);
    if (plates) all.half_thickness.reserve(total);
    CellGrid index;
    index.spec = grid;
    for (int a = 0; a < 3; ++a)
        index.bricks[a] = static_cast<std::uint32_t>((grid.dims[a] + CellGrid::brick_size - 1) / CellGrid::brick_size);
    using Next = std::pair<std::uint64_t, std::size_t>; // a part's next key, the part
    std::priority_queue<Next, std::vector<Next>, std::greater<>> next;
    std::vector<std::size_t> taken(parts.size(), 0);
    for (std::size_t k = 0; k < parts.size(); ++k)
        if (!parts[k].key.empty()) next.push({parts[k].key.front(), k});
    while (!next.empty()) {
        const auto [key, k] = next.top();
        next.pop();
        UnfacedPlanes& from = parts[k];
        const std::size_t p = taken[k]++;
        all.centroid.push_back(from.centroid[p]);
        all.normal.push_back(from.normal[p]);
        all.count.push_back(from.count[p]);
        if (plates) all.half_thickness.push_back(from.half_thickness.empty() ? 0.f : from.half_thickness[p]);
        if (taken[k] < from.key.size())
            next.push({from.key[taken[k]], k});
        else
            from = UnfacedPlanes{};
        const std::uint64_t brick = key / CellGrid::brick_cells;
        if (index.brick_keys.empty() || index.brick_keys.back() != brick) {
            index.brick_keys.push_back(brick);
            index.brick_masks.push_back(0);
            index.brick_first.push_back(all.count.size() - 1);
        }
        index.brick_masks.back() |= std::uint64_t{1} << (key % CellGrid::brick_cells);
    }
    index.index_bricks();
    // Step 2 only ever negates a normal: the sign of each plane's largest component, before,
    // tells whether it turned.
    std::vector<std::int8_t> was(total);
    for (std::size_t p = 0; p < total; ++p) {
        const Vec& n = all.normal[p];
        const int a = std::abs(n[0]) >= std::abs(n[1]) && std::abs(n[0]) >= std::abs(n[2]) ? 0
                      : std::abs(n[1]) >= std::abs(n[2])                                   ? 1
                                                                                           : 2;
        was[p] = static_cast<std::int8_t>(n[a] < 0 ? -(a + 1) : a + 1);
    }
    Planes planes(index, std::move(all));
    orient_normals(planes, *survey.outside);
    PlaneFacing facing;
    for (std::size_t p = 0; p < total; ++p) {
        const int a = std::abs(was[p]) - 1;
        if ((planes.normal[p][a] < 0) != (was[p] < 0)) facing.turned.push_back(index.order_key(planes.cell[p]));
    }
    return facing;
}

FacedSheet faced_sheet(const CellGrid& part, double iso, const SheetSurvey& survey, const PlaneFacing& facing,
                       LinearParts linear, SeamRequest* seam) {
    FacedSheet faced;
    faced.mesh = extract(part, iso, linear, nullptr, {}, seam, {}, &survey, &facing, &faced.half);
    return faced;
}

SurveyPart sheet_survey_part(const CellGrid& part, double iso, const std::array<std::int64_t, 4>& own,
                             LinearParts linear) {
    // The planes as extract makes them, up to the layers' spreads.
    Planes planes(part, iso);
    estimate_normals(planes);
    const bool tubes = linear == LinearParts::tubes;
    if (tubes) estimate_tubes(planes);
    const auto owned = [&](std::size_t p) {
        const auto& c = planes.cell[p];
        return c[0] >= own[0] && c[0] < own[1] && c[1] >= own[2] && c[1] < own[3];
    };
    SurveyPart survey;
    if (!planes.scatter.empty()) {
        std::vector<double> spread, points, middle;
        layer_spreads(planes, part.spec.cell_size, spread, points, middle);
        survey.spreads = usable_spreads(spread, points, owned);
    }
    // One surface cell for each voxel of the outside's that holds some (OutsideSpace looks no further).
    const int shift = OutsideSpace::voxel_shift(part.spec.dims);
    for (std::size_t p = 0; p < planes.cell.size(); ++p)
        if (owned(p)) {
            const auto& c = planes.cell[p];
            survey.walls.push_back({c[0] >> shift << shift, c[1] >> shift << shift, c[2] >> shift << shift});
        }
    std::sort(survey.walls.begin(), survey.walls.end());
    survey.walls.erase(std::unique(survey.walls.begin(), survey.walls.end()), survey.walls.end());
    return survey;
}

SheetSurvey combined_survey(const std::vector<SurveyPart>& parts, const std::array<std::uint32_t, 3>& dims) {
    std::vector<double> spreads;
    std::vector<std::array<std::int64_t, 3>> walls;
    for (const SurveyPart& part : parts) {
        spreads.insert(spreads.end(), part.spreads.begin(), part.spreads.end());
        walls.insert(walls.end(), part.walls.begin(), part.walls.end());
    }
    SheetSurvey survey;
    survey.noise = median_spread(std::move(spreads));
    survey.outside = std::make_shared<const OutsideSpace>(dims, walls);
    return survey;
}

Mesh extract_sheet(const CellGrid& part, double iso, const SheetSurvey& survey, LinearParts linear, SeamRequest* seam) {
    return extract(part, iso, linear, nullptr, {}, seam, {}, &survey);
}

} // namespace lasmesh
