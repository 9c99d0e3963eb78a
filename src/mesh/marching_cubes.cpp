// Marching cubes in three parallel passes, in the spirit of flying edges (Schroeder et al.
// 2015): count vertices and triangles per z layer, prefix-sum the counts, then fill
// preallocated arrays. No locks and no vertex hash map; every output index comes from the
// counts, so the mesh is identical for any number of threads.
#include "lasmesh/mesh/marching_cubes.hpp"

#include "lasmesh/error.hpp"
#include "lasmesh/mesh/marching_cubes_table.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace lasmesh {

namespace {

// The padded sample lattice: point (i, j, k) is the centre of cell (i-1, j-1, k-1); the outer
// layer is empty.
struct Lattice {
    const DensityGrid& grid;
    std::int64_t nx, ny, nz; // lattice points per axis (cells + 2)
    double level;            // interpolation level
    double iso;              // inside means count > iso

    VertexPlacement placement;

    explicit Lattice(const DensityGrid& g, double iso_value, VertexPlacement p)
        : grid(g), nx(g.spec.dims[0] + 2), ny(g.spec.dims[1] + 2), nz(g.spec.dims[2] + 2),
          level(std::floor(iso_value) == iso_value ? iso_value + 0.5 : iso_value), iso(iso_value), placement(p) {}

    std::int64_t cell(std::int64_t i, std::int64_t j, std::int64_t k) const {
        if (i < 1 || j < 1 || k < 1 || i > nx - 2 || j > ny - 2 || k > nz - 2) return -1;
        return ((k - 1) * (ny - 2) + (j - 1)) * (nx - 2) + (i - 1);
    }
    double value(std::int64_t i, std::int64_t j, std::int64_t k) const {
        const std::int64_t c = cell(i, j, k);
        return c < 0 ? 0.0 : static_cast<double>(grid.count[c]);
    }
    bool inside(std::int64_t i, std::int64_t j, std::int64_t k) const { return value(i, j, k) > iso; }
    // Whether the lattice edge from (i, j, k) along `axis` crosses the surface.
    bool crossed(std::int64_t i, std::int64_t j, std::int64_t k, int axis) const {
        if ((axis == 0 && i + 1 >= nx) || (axis == 1 && j + 1 >= ny) || (axis == 2 && k + 1 >= nz)) return false;
        return inside(i, j, k) != inside(i + (axis == 0), j + (axis == 1), k + (axis == 2));
    }
    // Where the vertex of a crossed edge lies, as a fraction of the way from (i, j, k) to its
    // neighbour along `axis`; always strictly inside the edge.
    double edge_fraction(std::int64_t i, std::int64_t j, std::int64_t k, int axis) const {
        const std::int64_t di = axis == 0, dj = axis == 1, dk = axis == 2;
        const double v0 = value(i, j, k), v1 = value(i + di, j + dj, k + dk);
        if (placement == VertexPlacement::iso) return (level - v0) / (v1 - v0);
        // Surface placement. A scanned surface fills a layer of cells one or two thick; across
        // it, along this edge, the counts run (beyond, inside, outside). Half of the layer's
        // count, beyond + inside, is the level at the layer's middle, so a vertex placed there
        // sits on the cell face for a one-cell layer and moves in as the layer spreads over two.
        // Never below the iso level, and never nearer the inside sample than a tenth of the edge
        // (a vertex strictly inside every edge keeps every triangle's area above zero).
        const bool first_inside = v0 > iso;
        const double inside = first_inside ? v0 : v1, outside = first_inside ? v1 : v0;
        const double beyond = first_inside ? value(i - di, j - dj, k - dk) : value(i + 2 * di, j + 2 * dj, k + 2 * dk);
        const double surface = std::min(std::max(level, 0.5 * (inside + beyond)), inside - 0.1 * (inside - outside));
        return (surface - v0) / (v1 - v0);
    }
    int cube_case(std::int64_t i, std::int64_t j, std::int64_t k) const {
        int mask = 0;
        for (int c = 0; c < 8; ++c) mask |= inside(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)) << c;
        return mask;
    }
};

// Vertex ids of the crossed edges whose lower end lies in layer k, by (j, i, axis); -1 elsewhere.
void layer_vertex_ids(const Lattice& l, std::int64_t k, std::uint32_t first, std::vector<std::int64_t>& ids) {
    ids.assign(l.nx * l.ny * 3, -1);
    std::uint32_t next = first;
    for (std::int64_t j = 0; j < l.ny; ++j)
        for (std::int64_t i = 0; i < l.nx; ++i)
            for (int a = 0; a < 3; ++a)
                if (l.crossed(i, j, k, a)) ids[(j * l.nx + i) * 3 + a] = next++;
}

} // namespace

double automatic_iso(const DensityGrid& grid) {
    std::vector<std::uint64_t> occupied;
    for (std::uint64_t c : grid.count)
        if (c > 0) occupied.push_back(c);
    if (occupied.empty()) return 1;
    auto middle = occupied.begin() + occupied.size() / 2;
    std::nth_element(occupied.begin(), middle, occupied.end());
    return std::max(1.0, std::floor(0.1 * static_cast<double>(*middle)));
}

Mesh extract_isosurface(const DensityGrid& grid, double iso, VertexPlacement placement) {
    const Lattice l(grid, iso, placement);
    const CubeEdges& edges = cube_edges();
    const CaseTable& table = case_table();

    // Pass 1: per layer, the crossed edges starting in it and the triangles of its cubes.
    std::vector<std::uint64_t> vertices_in(l.nz + 1, 0), triangles_in(l.nz + 1, 0);
    tbb::parallel_for(std::int64_t{0}, l.nz, [&](std::int64_t k) {
        std::uint64_t v = 0, t = 0;
        for (std::int64_t j = 0; j < l.ny; ++j)
            for (std::int64_t i = 0; i < l.nx; ++i) {
                for (int a = 0; a < 3; ++a) v += l.crossed(i, j, k, a);
                if (i + 1 < l.nx && j + 1 < l.ny && k + 1 < l.nz) t += table.triangles[l.cube_case(i, j, k)].size();
            }
        vertices_in[k + 1] = v;
        triangles_in[k + 1] = t;
    });
    // Pass 2: prefix sums give each layer its place in the output.
    for (std::int64_t k = 0; k < l.nz; ++k) {
        vertices_in[k + 1] += vertices_in[k];
        triangles_in[k + 1] += triangles_in[k];
    }
    if (vertices_in[l.nz] > UINT32_MAX)
        throw Error(ErrorKind::usage, "the mesh would have more than 2^32 vertices; use a smaller --grid");

    Mesh mesh;
    mesh.origin = grid.spec.origin;
    mesh.cell_size = grid.spec.cell_size;
    mesh.positions.resize(vertices_in[l.nz]);
    if (grid.has_color()) mesh.colors.resize(vertices_in[l.nz]);
    mesh.triangles.resize(triangles_in[l.nz]);
    const double h = grid.spec.cell_size;

    // Pass 3: fill vertices and triangles, each layer at its own offsets.
    tbb::parallel_for(std::int64_t{0}, l.nz, [&](std::int64_t k) {
        std::uint64_t v = vertices_in[k];
        for (std::int64_t j = 0; j < l.ny; ++j)
            for (std::int64_t i = 0; i < l.nx; ++i)
                for (int a = 0; a < 3; ++a) {
                    if (!l.crossed(i, j, k, a)) continue;
                    const std::int64_t i1 = i + (a == 0), j1 = j + (a == 1), k1 = k + (a == 2);
                    const double v0 = l.value(i, j, k), v1 = l.value(i1, j1, k1);
                    const double t = l.edge_fraction(i, j, k, a);
                    const double p[3] = {static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)};
                    auto& out = mesh.positions[v];
                    // Lattice point p is the centre of cell p - 1: at (p - 0.5) cells from the origin.
                    for (int c = 0; c < 3; ++c) out[c] = static_cast<float>((p[c] - 0.5 + (c == a ? t : 0.0)) * h);
                    if (grid.has_color()) {
                        const std::int64_t c0 = l.cell(i, j, k), c1 = l.cell(i1, j1, k1);
                        const double w0 = c0 < 0 ? 0 : (1 - t) * v0, w1 = c1 < 0 ? 0 : t * v1;
                        const Rgb8 a0 = c0 < 0 ? Rgb8{} : grid.mean_color(c0), a1 = c1 < 0 ? Rgb8{} : grid.mean_color(c1);
                        for (int c = 0; c < 3; ++c)
                            mesh.colors[v][c] = static_cast<std::uint8_t>(std::lround((w0 * a0[c] + w1 * a1[c]) / (w0 + w1)));
                    }
                    ++v;
                }
        if (k + 1 >= l.nz) return;
        std::vector<std::int64_t> below, above;
        layer_vertex_ids(l, k, static_cast<std::uint32_t>(vertices_in[k]), below);
        layer_vertex_ids(l, k + 1, static_cast<std::uint32_t>(vertices_in[k + 1]), above);
        std::uint64_t t = triangles_in[k];
        for (std::int64_t j = 0; j + 1 < l.ny; ++j)
            for (std::int64_t i = 0; i + 1 < l.nx; ++i)
                for (const auto& tri : table.triangles[l.cube_case(i, j, k)]) {
                    for (int n = 0; n < 3; ++n) {
                        const int e = tri[n], corner = edges.corners[e][0];
                        const std::int64_t ci = i + (corner & 1), cj = j + ((corner >> 1) & 1);
                        const auto& layer = (corner >> 2) & 1 ? above : below;
                        mesh.triangles[t][n] = static_cast<std::uint32_t>(layer[(cj * l.nx + ci) * 3 + e / 4]);
                    }
                    ++t;
                }
    });
    return mesh;
}

} // namespace lasmesh
