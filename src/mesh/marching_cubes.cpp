// SPDX-License-Identifier: Apache-2.0
// The closed surface of the grid of point counts: marching cubes over the count samples at the cell
// centres, visiting only the bricks near occupied cells (sparse_marching_cubes.hpp).
#include "mesh/marching_cubes.hpp"

#include "lasmesh/error.hpp"
#include "lasmesh/normals.hpp"
#include "sparse_marching_cubes.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace lasmesh {

namespace {

// The closed surface between cells with count > iso (inside) and the others. Lattice point
// (x, y, z) is the centre of cell (x - 1, y - 1, z - 1); the outer layer is padding, empty, so
// every surface closes.
struct DensityField {
    const CellGrid& grid;
    std::array<std::int64_t, 3> points; // cells + 2 per axis
    double level;                       // interpolation level
    double iso;                         // inside means count > iso
    VertexPlacement placement;

    DensityField(const CellGrid& g, double iso_value, VertexPlacement p)
        : grid(g), points{g.spec.dims[0] + 2, g.spec.dims[1] + 2, g.spec.dims[2] + 2},
          level(std::floor(iso_value) == iso_value ? iso_value + 0.5 : iso_value), iso(iso_value), placement(p) {}

    double value(std::int64_t x, std::int64_t y, std::int64_t z) const {
        return static_cast<double>(grid.count(x - 1, y - 1, z - 1));
    }
    detail::FieldSample sample(std::int64_t x, std::int64_t y, std::int64_t z) const {
        if (x < 0 || y < 0 || z < 0 || x >= points[0] || y >= points[1] || z >= points[2]) return {};
        const double v = value(x, y, z);
        return {static_cast<float>(v), 0, true, v > iso};
    }
    // Each sample is one cell's count: nothing to share between a brick's samples.
    const DensityField& sampler(const std::array<std::int64_t, 3>&, std::int64_t) const { return *this; }
    bool accepts(const detail::FieldSample&, const detail::FieldSample&) const { return true; }

    // Where the vertex of a crossed edge lies, as a fraction of the way from p to its neighbour
    // along `axis`; always strictly inside the edge.
    double edge_fraction(const std::array<std::int64_t, 3>& p, int axis, double v0, double v1) const {
        if (placement == VertexPlacement::iso) return (level - v0) / (v1 - v0);
        // Surface placement. A scanned surface fills a layer of cells one or two thick; across
        // it, along this edge, the counts run (beyond, inside, outside). Half of the layer's
        // count, beyond + inside, is the level at the layer's middle, so a vertex placed there
        // sits on the cell face for a one-cell layer and moves in as the layer spreads over two.
        // Never below the iso level, and never nearer the inside sample than a tenth of the edge
        // (a vertex strictly inside every edge keeps every triangle's area above zero).
        const std::int64_t di = axis == 0, dj = axis == 1, dk = axis == 2;
        const bool first_inside = v0 > iso;
        const double inside = first_inside ? v0 : v1, outside = first_inside ? v1 : v0;
        const double beyond =
            first_inside ? value(p[0] - di, p[1] - dj, p[2] - dk) : value(p[0] + 2 * di, p[1] + 2 * dj, p[2] + 2 * dk);
        const double surface = std::min(std::max(level, 0.5 * (inside + beyond)), inside - 0.1 * (inside - outside));
        return (surface - v0) / (v1 - v0);
    }
    void vertex(const std::array<std::int64_t, 3>& p, int axis, const detail::FieldSample& s0,
                const detail::FieldSample& s1, detail::VertexOut& out) const {
        const std::array<std::int64_t, 3> q{p[0] + (axis == 0), p[1] + (axis == 1), p[2] + (axis == 2)};
        const double v0 = s0.value, v1 = s1.value;
        const double t = edge_fraction(p, axis, v0, v1);
        const double h = grid.spec.cell_size;
        // Lattice point p is the centre of cell p - 1: at (p - 0.5) cells from the origin.
        for (int c = 0; c < 3; ++c) out.position[c] = static_cast<float>((p[c] - 0.5 + (c == axis ? t : 0.0)) * h);
        if (grid.has_color()) {
            const CellSums* c0 = grid.find(p[0] - 1, p[1] - 1, p[2] - 1);
            const CellSums* c1 = grid.find(q[0] - 1, q[1] - 1, q[2] - 1);
            const double w0 = c0 ? (1 - t) * v0 : 0, w1 = c1 ? t * v1 : 0;
            const Rgb8 a0 = c0 ? grid.mean_color(*c0) : Rgb8{}, a1 = c1 ? grid.mean_color(*c1) : Rgb8{};
            for (int c = 0; c < 3; ++c)
                out.color[c] = static_cast<std::uint8_t>(std::lround((w0 * a0[c] + w1 * a1[c]) / (w0 + w1)));
        }
    }
};

} // namespace

double automatic_iso(const CellGrid& grid) {
    return automatic_iso(grid.median_count());
}

double automatic_iso(std::uint64_t median_count) {
    return std::max(1.0, std::floor(0.1 * static_cast<double>(median_count)));
}

Mesh extract_closed_surface(const CellGrid& grid, double iso, VertexPlacement placement) {
    const DensityField field(grid, iso, placement);
    Mesh mesh = detail::march_sparse(field, detail::lattice_near_data(grid, field.points), grid.has_color());
    // A count field's gradient is too noisy for shading: the faces' normals instead.
    compute_vertex_normals(mesh);
    mesh.origin = grid.spec.origin;
    mesh.cell_size = grid.spec.cell_size;
    return mesh;
}

} // namespace lasmesh
