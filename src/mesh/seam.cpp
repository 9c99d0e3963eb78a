// SPDX-License-Identifier: Apache-2.0
// append_joined: the seam between the coarse mesh and the fine mesh of the thin parts, the fine
// border laid onto the coarse one where they run side by side (Shu, Zhou & Kankanhalli 1995's
// crack patching, across cell faces).
#include "mesh/seam.hpp"

#include "grid/cell_set.hpp"
#include "grid/thin_parts.hpp"
#include "mesh/mesh_edit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <tuple>

namespace lasmesh {

namespace {

using V3 = std::array<double, 3>;
constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

V3 position(const Mesh& m, std::uint32_t v) {
    return {m.positions[v][0], m.positions[v][1], m.positions[v][2]};
}

// Whether a coordinate lies on a plane of the coarse lattice, and which. Both meshes write a
// lattice coordinate as float(k h), the fine one as float(2k (h / 2)): the same number.
bool on_plane(float coordinate, double h, std::int64_t& k) {
    k = std::llround(static_cast<double>(coordinate) / h);
    return static_cast<float>(static_cast<double>(k) * h) == coordinate;
}

// The edge of the coarse lattice a vertex lies on: along `axis`, from corner `corner`; axis 3
// when it lies on none (a fine vertex inside a face).
struct LatticeEdge {
    int axis = 3;
    std::array<std::int64_t, 3> corner{};
    bool operator==(const LatticeEdge&) const = default;
};

LatticeEdge lattice_edge(const Mesh& m, std::uint32_t v, double h) {
    std::array<std::int64_t, 3> k{};
    int off = 3, count = 0;
    for (int a = 0; a < 3; ++a)
        if (on_plane(m.positions[v][a], h, k[a]))
            ++count;
        else
            off = a;
    if (count != 2) return {};
    k[off] = static_cast<std::int64_t>(std::floor(static_cast<double>(m.positions[v][off]) / h));
    return {off, k};
}

// A cell face of the seam: the plane `axis` = k h, the square (i, j) on it (the two other axes in
// order).
using FaceKey = std::tuple<int, std::int64_t, std::int64_t, std::int64_t>;

// A border edge of one of the meshes, a -> b as its triangle `triangle` winds, on a face of the seam.
struct SeamEdge {
    FaceKey face;
    std::uint32_t a, b, triangle;
    bool operator<(const SeamEdge& o) const { return std::tie(face, a, b) < std::tie(o.face, o.a, o.b); }
};

// The bricks of the grid (CellGrid::brick_size cells an edge) within a brick of a cell of
// `fine_cells`. A triangle with an edge on a face of the seam lies in a cell that holds that
// edge, next to the face, and its centroid at most on that cell's far side: only triangles whose
// centroid lies in these bricks can share such an edge, so the others need not be looked at.
struct NearSeam {
    std::array<std::int64_t, 3> bricks{};
    CellSet near;
};
NearSeam near_seam(const GridSpec& grid, const std::vector<std::uint64_t>& fine_cells) {
    NearSeam n;
    for (int a = 0; a < 3; ++a)
        n.bricks[a] = (std::int64_t{grid.dims[a]} + CellGrid::brick_size - 1) >> CellGrid::brick_bits;
    std::vector<std::array<std::int64_t, 3>> cells;
    cells.reserve(fine_cells.size());
    for (const std::uint64_t key : fine_cells)
        cells.push_back({std::int64_t(key % grid.dims[0]), std::int64_t(key / grid.dims[0] % grid.dims[1]),
                         std::int64_t(key / grid.dims[0] / grid.dims[1])});
    n.near = CellSet(blocks_around(cells, n.bricks, CellGrid::brick_bits, 1), n.bricks);
    return n;
}

// The border edges of `m` that lie on a face between a cell of `fine_cells` and one that is not.
std::vector<SeamEdge> seam_edges(const Mesh& m, const GridSpec& grid, const std::vector<std::uint64_t>& fine_cells,
                                 const NearSeam& near) {
    struct Edge {
        std::uint64_t key;
        std::uint32_t triangle;
        int at;
        bool operator<(const Edge& o) const { return std::tie(key, triangle, at) < std::tie(o.key, o.triangle, o.at); }
    };
    std::vector<Edge> edges;
    const double h = grid.cell_size;
    for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
        std::array<std::int64_t, 3> brick{};
        bool inside = true;
        for (int x = 0; x < 3; ++x) {
            const double centroid = (static_cast<double>(m.positions[m.triangles[t][0]][x]) +
                                     m.positions[m.triangles[t][1]][x] + m.positions[m.triangles[t][2]][x]) /
                                    3;
            brick[x] = static_cast<std::int64_t>(std::floor(centroid / h)) >> CellGrid::brick_bits;
            inside = inside && brick[x] >= 0 && brick[x] < near.bricks[x];
        }
        if (!inside || !near.near.contains(std::uint64_t(brick[0]), std::uint64_t(brick[1]), std::uint64_t(brick[2])))
            continue;
        for (int e = 0; e < 3; ++e) {
            const std::uint64_t a = m.triangles[t][e], b = m.triangles[t][(e + 1) % 3];
            edges.push_back({std::min(a, b) << 32 | std::max(a, b), t, e});
        }
    }
    std::sort(edges.begin(), edges.end());
    const auto in_grid = [&](const std::array<std::int64_t, 3>& c) {
        for (int a = 0; a < 3; ++a)
            if (c[a] < 0 || c[a] >= static_cast<std::int64_t>(grid.dims[a])) return false;
        return true;
    };
    const auto fine = [&](const std::array<std::int64_t, 3>& c) {
        const std::uint64_t key =
            (std::uint64_t(c[2]) * grid.dims[1] + std::uint64_t(c[1])) * grid.dims[0] + std::uint64_t(c[0]);
        return std::binary_search(fine_cells.begin(), fine_cells.end(), key);
    };
    std::vector<SeamEdge> seam;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j].key == edges[i].key) ++j;
        if (j - i == 1) { // a border edge
            const auto& t = m.triangles[edges[i].triangle];
            const std::uint32_t a = t[edges[i].at], b = t[(edges[i].at + 1) % 3];
            int axis = -1, planes = 0;
            std::int64_t k = 0;
            for (int x = 0; x < 3; ++x) {
                std::int64_t ka = 0, kb = 0;
                if (on_plane(m.positions[a][x], h, ka) && on_plane(m.positions[b][x], h, kb) && ka == kb)
                    axis = x, k = ka, ++planes;
            }
            if (planes == 1) {
                std::array<std::int64_t, 3> below{}, above{};
                for (int x = 0; x < 3; ++x) {
                    const double mid = (static_cast<double>(m.positions[a][x]) + m.positions[b][x]) / 2;
                    below[x] = above[x] = static_cast<std::int64_t>(std::floor(mid / h));
                }
                below[axis] = k - 1, above[axis] = k;
                if (in_grid(below) && in_grid(above) && fine(below) != fine(above))
                    seam.push_back({{axis, k, above[(axis + 1) % 3], above[(axis + 2) % 3]}, a, b, edges[i].triangle});
            }
        }
        i = j;
    }
    std::sort(seam.begin(), seam.end());
    return seam;
}

// The chains of fine border edges on one face, each from a vertex no edge enters; empty when the
// edges do not form simple chains (a vertex with two edges out or in, a loop).
std::vector<std::vector<std::uint32_t>> chains_of(const std::vector<SeamEdge>& edges) {
    std::vector<std::vector<std::uint32_t>> chains;
    std::vector<char> used(edges.size(), 0);
    for (std::size_t i = 0; i < edges.size(); ++i) {
        std::size_t into = 0, out = 0;
        for (const SeamEdge& e : edges) into += e.b == edges[i].a, out += e.a == edges[i].a;
        if (out != 1 || into > 1) return {};
        if (into == 1) continue;
        std::vector<std::uint32_t> chain{edges[i].a};
        for (std::size_t at = i;;) {
            used[at] = 1;
            chain.push_back(edges[at].b);
            std::size_t next = edges.size();
            for (std::size_t k = 0; k < edges.size(); ++k)
                if (edges[k].a == edges[at].b) next = k;
            if (next == edges.size()) break;
            if (used[next]) return {};
            at = next;
        }
        chains.push_back(std::move(chain));
    }
    if (std::count(used.begin(), used.end(), 0) != 0) return {}; // a loop
    return chains;
}

// Calls `each` for every face with seam edges of both meshes (both lists in face order), with
// the face's coarse edges in `segments` and its fine ones in `pieces`.
template <typename Each>
void for_each_face(const std::vector<SeamEdge>& coarse_seam, const std::vector<SeamEdge>& fine_seam,
                   std::vector<SeamEdge>& segments, std::vector<SeamEdge>& pieces, Each each) {
    for (std::size_t c = 0, f = 0; c < coarse_seam.size() && f < fine_seam.size();) {
        if (coarse_seam[c].face < fine_seam[f].face) {
            ++c;
            continue;
        }
        if (fine_seam[f].face < coarse_seam[c].face) {
            ++f;
            continue;
        }
        const FaceKey face = coarse_seam[c].face;
        segments.clear(), pieces.clear();
        for (; c < coarse_seam.size() && coarse_seam[c].face == face; ++c) segments.push_back(coarse_seam[c]);
        for (; f < fine_seam.size() && fine_seam[f].face == face; ++f) pieces.push_back(fine_seam[f]);
        each();
    }
}

// Whether a chain and the coarse segments of its face run between the same two cell edges: +1
// the opposite way round (both surfaces face the same side), -1 the same way, 0 neither.
int agreement(const Mesh& coarse, const Mesh& fine, const std::vector<SeamEdge>& segments,
              const std::vector<std::uint32_t>& chain, double h) {
    const LatticeEdge from = lattice_edge(fine, chain.front(), h), to = lattice_edge(fine, chain.back(), h);
    if (from.axis == 3 || to.axis == 3 || from == to) return 0;
    for (const SeamEdge& s : segments) {
        const LatticeEdge a = lattice_edge(coarse, s.a, h), b = lattice_edge(coarse, s.b, h);
        if (b == from && a == to) return 1;
        if (a == from && b == to) return -1;
    }
    return 0;
}

// Turns each connected part of `fine` that meets the coarse mesh facing the other way on most
// of the faces where they meet: the two sheets are oriented each on its own, and a fine part
// continues the coarse surface around it.
void face_as_coarse(Mesh& fine, const Mesh& coarse, const std::vector<SeamEdge>& coarse_seam,
                    const std::vector<SeamEdge>& fine_seam, double h) {
    const std::vector<std::uint32_t> part = connected_parts(fine);
    std::vector<long> votes(fine.positions.size(), 0); // per part
    std::vector<SeamEdge> segments, pieces;
    for_each_face(coarse_seam, fine_seam, segments, pieces, [&] {
        for (const std::vector<std::uint32_t>& chain : chains_of(pieces))
            votes[part[chain.front()]] += agreement(coarse, fine, segments, chain, h);
    });
    std::vector<char> turn(fine.positions.size(), 0);
    for (std::uint32_t v = 0; v < turn.size(); ++v) turn[v] = votes[part[v]] < 0;
    turn_over(fine, turn);
}

V3 normal_of(const std::array<V3, 3>& t) {
    const V3 u{t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]};
    const V3 w{t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]};
    return {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
}

double length_of(const Mesh& m, const std::vector<SeamEdge>& edges) {
    double sum = 0;
    for (const SeamEdge& e : edges) {
        const V3 a = position(m, e.a), b = position(m, e.b);
        sum += std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    }
    return sum;
}

// One mesh's border along the seam: its seam edges end to end, across faces. Edge k runs from
// vertices[k] to vertices[k + 1] as triangle triangles[k] winds. A border ends where a vertex
// has other than one seam edge in and one out (or where the border leaves the seam); a loop
// starts at its first edge in face order and ends on that edge's first vertex.
struct Border {
    std::vector<std::uint32_t> vertices;
    std::vector<std::uint32_t> triangles;
};

std::vector<Border> borders_of(const std::vector<SeamEdge>& seam) {
    std::vector<std::pair<std::uint32_t, std::size_t>> out, into; // (vertex, edge)
    for (std::size_t i = 0; i < seam.size(); ++i) out.emplace_back(seam[i].a, i), into.emplace_back(seam[i].b, i);
    std::sort(out.begin(), out.end());
    std::sort(into.begin(), into.end());
    const auto count = [&](const auto& list, std::uint32_t v) {
        const auto lo = std::lower_bound(list.begin(), list.end(), std::pair{v, std::size_t{0}});
        std::size_t n = 0;
        for (auto it = lo; it != list.end() && it->first == v; ++it) ++n;
        return std::pair{n, lo == list.end() ? seam.size() : lo->second};
    };
    // The edge that continues edge i, or seam.size().
    const auto next = [&](std::size_t i) {
        const auto [outs, edge] = count(out, seam[i].b);
        return outs == 1 && count(into, seam[i].b).first == 1 ? edge : seam.size();
    };
    std::vector<Border> borders;
    std::vector<char> used(seam.size(), 0);
    const auto walk = [&](std::size_t i) {
        Border b{{seam[i].a}, {}};
        for (; i < seam.size() && !used[i]; i = next(i)) {
            used[i] = 1;
            b.vertices.push_back(seam[i].b), b.triangles.push_back(seam[i].triangle);
        }
        borders.push_back(std::move(b));
    };
    for (std::size_t i = 0; i < seam.size(); ++i)
        if (count(out, seam[i].a).first != 1 || count(into, seam[i].a).first != 1) walk(i);
    for (std::size_t i = 0; i < seam.size(); ++i)
        if (!used[i]) walk(i); // loops
    return borders;
}

// Where a fine vertex lies on the coarse borders: border `border`, at s = k + t on its edge k
// (t from 0 at vertices[k] to 1 at vertices[k + 1]); `border` none when no coarse border edge
// passes within half a cell.
struct Place {
    std::uint32_t border = none;
    double s = 0;
    V3 at{};
};

// The coarse borders' edges by the cell of their midpoint, to find those near a point.
class NearEdges {
  public:
    NearEdges(const Mesh& coarse, const std::vector<Border>& borders, double h)
        : coarse_(coarse), borders_(borders), h_(h) {
        for (std::uint32_t b = 0; b < borders.size(); ++b)
            for (std::uint32_t k = 0; k + 1 < borders[b].vertices.size(); ++k) {
                const V3 p = position(coarse, borders[b].vertices[k]), q = position(coarse, borders[b].vertices[k + 1]);
                edges_.push_back({cell_of({(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2}), b, k});
            }
        std::sort(edges_.begin(), edges_.end());
    }

    // The nearest coarse border edge within half a cell of `x` (the first in border order of
    // those as near), and the nearest point on it.
    Place nearest(const V3& x) const {
        Place best;
        double best_d2 = h_ * h_ / 4;
        const Cell c = cell_of(x);
        // An edge lies in a cell face (at most a face's diagonal long), so one within half a cell
        // has its midpoint within 1.21 cells: two cells either way.
        for (std::int64_t dz = -2; dz <= 2; ++dz)
            for (std::int64_t dy = -2; dy <= 2; ++dy)
                for (std::int64_t dx = -2; dx <= 2; ++dx) {
                    const Cell n{c[0] + dx, c[1] + dy, c[2] + dz};
                    auto it = std::lower_bound(edges_.begin(), edges_.end(), Edge{n, 0, 0});
                    for (; it != edges_.end() && it->cell == n; ++it) {
                        const Border& b = borders_[it->border];
                        const V3 p = position(coarse_, b.vertices[it->k]), q = position(coarse_, b.vertices[it->k + 1]);
                        const V3 pq{q[0] - p[0], q[1] - p[1], q[2] - p[2]};
                        const double l2 = pq[0] * pq[0] + pq[1] * pq[1] + pq[2] * pq[2];
                        if (!(l2 > 0)) continue;
                        const double t = std::clamp(
                            ((x[0] - p[0]) * pq[0] + (x[1] - p[1]) * pq[1] + (x[2] - p[2]) * pq[2]) / l2, 0.0, 1.0);
                        const V3 on{p[0] + t * pq[0], p[1] + t * pq[1], p[2] + t * pq[2]};
                        const double d2 = (x[0] - on[0]) * (x[0] - on[0]) + (x[1] - on[1]) * (x[1] - on[1]) +
                                          (x[2] - on[2]) * (x[2] - on[2]);
                        if (d2 < best_d2 ||
                            (d2 == best_d2 && std::pair{it->border, it->k + t} < std::pair{best.border, best.s})) {
                            best_d2 = d2;
                            best = {it->border, it->k + t, on};
                        }
                    }
                }
        return best;
    }

  private:
    using Cell = std::array<std::int64_t, 3>;
    struct Edge {
        Cell cell;
        std::uint32_t border, k;
        bool operator<(const Edge& o) const { return std::tie(cell, border, k) < std::tie(o.cell, o.border, o.k); }
    };
    Cell cell_of(const V3& x) const {
        return {static_cast<std::int64_t>(std::floor(x[0] / h_)), static_cast<std::int64_t>(std::floor(x[1] / h_)),
                static_cast<std::int64_t>(std::floor(x[2] / h_))};
    }
    const Mesh& coarse_;
    const std::vector<Border>& borders_;
    double h_;
    std::vector<Edge> edges_;
};

// A stretch of a fine border laid onto a coarse one, the two running opposite ways (both faces
// on one side). Each coarse vertex the stretch passes takes one of its fine vertices (welded:
// the fine vertex becomes the coarse one); the others go onto the coarse edge they lie along,
// where the coarse triangle is split at them. So every fine edge of the stretch is an edge of
// the split coarse border, and the two meshes share it.
struct Stretch {
    std::uint32_t border;            // the coarse border
    std::vector<std::uint32_t> fine; // the fine vertices, in the fine border's order
    std::vector<std::uint32_t> weld; // per fine vertex: the coarse vertex's index in the border, or none
    std::vector<double> s;           // per fine vertex: where on the coarse border (falling; a weld's vertex)
    std::vector<V3> at;              // and its place there
};

// The longest stretch from fine vertex `from` of `fine_border` (whose places are `places`) onto
// the coarse border of its first place, or one of fewer than two vertices when none.
Stretch lay(const Mesh& fine, const Mesh& coarse, const Border& fine_border, const std::vector<Place>& places,
            std::size_t from, const Border& coarse_border, double h) {
    constexpr double gap = 1e-3; // the least step between two places, in edges
    const std::uint32_t b = places[from].border;
    std::size_t to = from + 1; // one past the last vertex whose places fall along border b
    while (to < places.size() && places[to].border == b && places[to].s < places[to - 1].s - gap) ++to;
    Stretch st{b, {}, {}, {}, {}};
    const std::size_t n = to - from;
    std::vector<std::uint32_t> weld(n, none);
    const auto s = [&](std::size_t j) { return places[from + j].s; };
    const auto near = [&](std::size_t j, std::uint32_t i) {
        const V3 x = position(fine, fine_border.vertices[from + j]), p = position(coarse, coarse_border.vertices[i]);
        return (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1]) + (x[2] - p[2]) * (x[2] - p[2]) <=
               h * h / 4;
    };
    // The coarse vertices the stretch passes, or ends a quarter of an edge from, highest first;
    // each welded to the nearer of the fine vertices either side of it (after the last welded).
    const auto last_vertex = static_cast<std::int64_t>(coarse_border.vertices.size()) - 1;
    const auto hi = std::min<std::int64_t>(last_vertex, static_cast<std::int64_t>(std::floor(s(0) + 0.25)));
    const auto lo = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil(s(n - 1) - 0.25)));
    std::size_t kept = n;
    std::int64_t welded_last = -1;
    std::int64_t above = -1; // the last fine vertex at or above coarse vertex i
    for (std::int64_t i = hi; i >= lo; --i) {
        while (above + 1 < static_cast<std::int64_t>(n) &&
               s(static_cast<std::size_t>(above + 1)) >= static_cast<double>(i))
            ++above;
        std::int64_t pick = -1;
        double pick_off = 0;
        for (const std::int64_t j : {above, above + 1}) {
            if (j <= welded_last || j >= static_cast<std::int64_t>(n)) continue;
            const double off = std::abs(s(static_cast<std::size_t>(j)) - static_cast<double>(i));
            if (!near(static_cast<std::size_t>(j), static_cast<std::uint32_t>(i))) continue;
            if (pick < 0 || off < pick_off) pick = j, pick_off = off;
        }
        if (pick < 0) { // the stretch ends above this coarse vertex
            kept = static_cast<std::size_t>(std::max<std::int64_t>(above + 1, 0));
            break;
        }
        weld[static_cast<std::size_t>(pick)] = static_cast<std::uint32_t>(i), welded_last = pick;
    }
    // The places in order: the welded at their vertices, the others strictly between.
    double last = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < kept; ++j) {
        const double at = weld[j] != none ? static_cast<double>(weld[j]) : s(j);
        const bool on_vertex = weld[j] == none && std::abs(at - std::round(at)) < gap;
        if (!(at < last - gap) || on_vertex) {
            kept = j;
            break;
        }
        last = at;
    }
    // The stretch, up to the first vertex out of that order.
    for (std::size_t j = 0; j < kept; ++j) {
        st.fine.push_back(fine_border.vertices[from + j]);
        st.weld.push_back(weld[j]);
        st.s.push_back(weld[j] != none ? static_cast<double>(weld[j]) : s(j));
        st.at.push_back(weld[j] != none ? position(coarse, coarse_border.vertices[weld[j]]) : places[from + j].at);
    }
    if (st.fine.empty()) { // nothing laid from here: the next vertex starts again
        st.fine.push_back(fine_border.vertices[from]);
        st.weld.push_back(none), st.s.push_back(s(0)), st.at.push_back(places[from].at);
    }
    return st;
}

} // namespace

SeamReport append_joined(Mesh& coarse, const Mesh& thin, const GridSpec& grid,
                         const std::vector<std::uint64_t>& fine_cells) {
    SeamReport report;
    const double h = grid.cell_size;
    Mesh fine = thin;
    const NearSeam near = near_seam(grid, fine_cells);
    const std::vector<SeamEdge> coarse_seam = seam_edges(coarse, grid, fine_cells, near);
    face_as_coarse(fine, coarse, coarse_seam, seam_edges(fine, grid, fine_cells, near), h);
    const std::vector<SeamEdge> fine_seam = seam_edges(fine, grid, fine_cells, near);
    report.open_before = length_of(coarse, coarse_seam) + length_of(fine, fine_seam);
    {
        std::vector<SeamEdge> segments, pieces;
        for_each_face(coarse_seam, fine_seam, segments, pieces, [&] { ++report.faces; });
    }
    // Each fine border laid onto the coarse borders near it, stretch by stretch.
    const std::vector<Border> coarse_borders = borders_of(coarse_seam);
    const NearEdges near_edges(coarse, coarse_borders, h);
    std::vector<Stretch> stretches;
    for (const Border& f : borders_of(fine_seam)) {
        std::vector<Place> places(f.vertices.size());
        for (std::size_t j = 0; j < places.size(); ++j) places[j] = near_edges.nearest(position(fine, f.vertices[j]));
        for (std::size_t j = 0; j < places.size();) {
            if (places[j].border == none) {
                ++j;
                continue;
            }
            Stretch st = lay(fine, coarse, f, places, j, coarse_borders[places[j].border], h);
            j += st.fine.size();
            if (st.fine.size() >= 2) stretches.push_back(std::move(st));
        }
    }
    // Longest first, a stretch is kept when none kept before has one of its fine vertices, welds
    // one of its coarse vertices or lies on the same coarse border across its span. What is not
    // kept stays open.
    std::vector<char> kept(stretches.size(), 0);
    {
        std::vector<std::size_t> order(stretches.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
            return stretches[x].fine.size() > stretches[y].fine.size();
        });
        std::vector<char> fine_used(fine.positions.size(), 0), coarse_used(coarse.positions.size(), 0);
        std::vector<std::vector<std::pair<double, double>>> spans(coarse_borders.size());
        for (const std::size_t i : order) {
            const Stretch& st = stretches[i];
            const Border& b = coarse_borders[st.border];
            const double low = st.s.back(), high = st.s.front();
            bool free = std::none_of(spans[st.border].begin(), spans[st.border].end(),
                                     [&](const auto& span) { return low <= span.second && span.first <= high; });
            std::vector<std::uint32_t> fines = st.fine, coarses;
            for (const std::uint32_t w : st.weld)
                if (w != none) coarses.push_back(b.vertices[w]);
            std::sort(fines.begin(), fines.end());
            std::sort(coarses.begin(), coarses.end());
            free = free && std::adjacent_find(fines.begin(), fines.end()) == fines.end() &&
                   std::adjacent_find(coarses.begin(), coarses.end()) == coarses.end() &&
                   std::none_of(fines.begin(), fines.end(), [&](std::uint32_t v) { return fine_used[v]; }) &&
                   std::none_of(coarses.begin(), coarses.end(), [&](std::uint32_t v) { return coarse_used[v]; });
            if (!free) continue;
            kept[i] = 1;
            for (const std::uint32_t v : fines) fine_used[v] = 1;
            for (const std::uint32_t v : coarses) coarse_used[v] = 1;
            spans[st.border].emplace_back(low, high);
        }
    }
    std::vector<std::vector<std::uint32_t>> fine_triangles_of(fine.positions.size());
    for (std::uint32_t t = 0; t < fine.triangles.size(); ++t)
        for (const std::uint32_t v : fine.triangles[t]) fine_triangles_of[v].push_back(t);
    // The fine mesh after the coarse one: its welded vertices are the coarse ones, its laid
    // vertices on the coarse border, where the coarse edges are split at them. A laid vertex next
    // to another stretch's end can give an edge the fine mesh has already (a fine triangle in the
    // seam's face): the stretches at an edge with more than two triangles, or two facing apart,
    // are left open, and the join made again without them.
    const auto first = static_cast<std::uint32_t>(coarse.positions.size());
    const auto coarse_triangles = static_cast<std::uint32_t>(coarse.triangles.size());
    std::vector<std::array<std::uint32_t, 3>> triangles;
    triangles.swap(fine.triangles);
    std::vector<V3> moved_to(fine.positions.size());
    std::vector<std::uint32_t> moved_by(fine.positions.size(), none);
    for (;;) {
        // No fine triangle turned over by the moves of the stretches kept (again after a clash
        // left some out).
        for (bool turned = true; turned;) {
            std::fill(moved_by.begin(), moved_by.end(), none);
            for (std::uint32_t i = 0; i < stretches.size(); ++i)
                if (kept[i])
                    for (std::size_t j = 0; j < stretches[i].fine.size(); ++j)
                        moved_to[stretches[i].fine[j]] = stretches[i].at[j], moved_by[stretches[i].fine[j]] = i;
            turned = false;
            for (std::uint32_t v = 0; v < fine.positions.size(); ++v) {
                if (moved_by[v] == none) continue;
                for (const std::uint32_t t : fine_triangles_of[v]) {
                    std::array<V3, 3> was{}, now{};
                    for (int k = 0; k < 3; ++k) {
                        const std::uint32_t w = triangles[t][k];
                        was[k] = now[k] = position(fine, w);
                        if (moved_by[w] != none) now[k] = moved_to[w];
                    }
                    const V3 a = normal_of(was), b = normal_of(now);
                    const double along = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
                    if (along > 0 &&
                        b[0] * b[0] + b[1] * b[1] + b[2] * b[2] > 1e-6 * (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]))
                        continue;
                    // Each stretch that moved a corner of it ends before that corner.
                    for (const std::uint32_t w : triangles[t])
                        if (moved_by[w] != none) {
                            Stretch& st = stretches[moved_by[w]];
                            const auto at = static_cast<std::size_t>(std::find(st.fine.begin(), st.fine.end(), w) -
                                                                     st.fine.begin());
                            st.fine.resize(at), st.weld.resize(at), st.s.resize(at), st.at.resize(at);
                            if (st.fine.size() < 2) kept[moved_by[w]] = 0;
                        }
                    turned = true;
                }
            }
        }
        std::vector<std::uint32_t> index(fine.positions.size()), owner(first + fine.positions.size(), none);
        for (std::uint32_t v = 0; v < fine.positions.size(); ++v) index[v] = first + v;
        std::vector<std::tuple<std::uint32_t, std::uint32_t, double, std::uint32_t>> splits; // (border, edge, t, fine)
        for (std::uint32_t i = 0; i < stretches.size(); ++i) {
            if (!kept[i]) continue;
            const Stretch& st = stretches[i];
            const Border& b = coarse_borders[st.border];
            for (std::size_t j = 0; j < st.fine.size(); ++j) {
                if (st.weld[j] != none) {
                    index[st.fine[j]] = b.vertices[st.weld[j]];
                    owner[b.vertices[st.weld[j]]] = i;
                    continue;
                }
                owner[first + st.fine[j]] = i;
                for (int a = 0; a < 3; ++a) fine.positions[st.fine[j]][a] = static_cast<float>(st.at[j][a]);
                const auto k = std::min<std::uint32_t>(static_cast<std::uint32_t>(st.s[j]),
                                                       static_cast<std::uint32_t>(b.triangles.size() - 1));
                splits.emplace_back(st.border, k, st.s[j] - k, st.fine[j]);
            }
        }
        std::sort(splits.begin(), splits.end());
        append_mesh(coarse, fine);
        for (auto t : triangles) {
            for (std::uint32_t& v : t) v = index[v];
            coarse.triangles.push_back(t);
        }
        // Each split coarse triangle (P, Q, R), P -> Q on the border, becomes a fan from R over
        // P, the laid vertices from P's end, and Q. A triangle with two edges on the border is
        // split on the second in the part of the fan that holds it: who holds each border edge
        // is followed.
        std::vector<std::pair<std::uint64_t, std::uint32_t>> holder; // (edge a << 32 | b, triangle)
        for (const SeamEdge& e : coarse_seam) holder.emplace_back(std::uint64_t{e.a} << 32 | e.b, e.triangle);
        std::sort(holder.begin(), holder.end());
        const auto held = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key = std::uint64_t{a} << 32 | b;
            const auto it = std::lower_bound(holder.begin(), holder.end(), std::pair{key, std::uint32_t{0}});
            return it != holder.end() && it->first == key ? &it->second : nullptr;
        };
        std::vector<std::pair<std::uint32_t, std::array<std::uint32_t, 3>>> split_from; // (triangle, as it was)
        for (std::size_t i = 0; i < splits.size();) {
            const auto [border, edge, t0, v0] = splits[i];
            const std::uint32_t p = coarse_borders[border].vertices[edge],
                                q = coarse_borders[border].vertices[edge + 1];
            std::vector<std::uint32_t> along{p};
            for (; i < splits.size() && std::get<0>(splits[i]) == border && std::get<1>(splits[i]) == edge; ++i)
                along.push_back(index[std::get<3>(splits[i])]);
            along.push_back(q);
            std::uint32_t* t = held(p, q);
            if (!t) continue;
            const std::array<std::uint32_t, 3> was = coarse.triangles[*t];
            int e = 0;
            while (e < 3 && !(was[e] == p && was[(e + 1) % 3] == q)) ++e;
            if (e == 3) continue;
            if (*t < coarse_triangles) split_from.emplace_back(*t, was);
            const std::uint32_t r = was[(e + 2) % 3];
            coarse.triangles[*t] = {along[0], along[1], r};
            for (std::size_t k = 1; k + 1 < along.size(); ++k) coarse.triangles.push_back({along[k], along[k + 1], r});
            if (std::uint32_t* next = held(q, r)) *next = static_cast<std::uint32_t>(coarse.triangles.size() - 1);
        }
        // The edges at the joined vertices: each between two triangles at most, facing one way.
        std::vector<std::uint32_t> local;
        for (std::uint32_t t = 0; t < coarse_triangles; ++t)
            if (owner[coarse.triangles[t][0]] != none || owner[coarse.triangles[t][1]] != none ||
                owner[coarse.triangles[t][2]] != none)
                local.push_back(t);
        for (std::uint32_t i = 0; i < stretches.size(); ++i) // welded corners too
            if (kept[i])
                for (const std::uint32_t v : stretches[i].fine)
                    for (const std::uint32_t t : fine_triangles_of[v]) local.push_back(coarse_triangles + t);
        for (const auto& [t, was] : split_from) local.push_back(t);
        for (auto t = static_cast<std::uint32_t>(coarse_triangles + triangles.size()); t < coarse.triangles.size(); ++t)
            local.push_back(t);
        std::sort(local.begin(), local.end());
        local.erase(std::unique(local.begin(), local.end()), local.end());
        std::vector<std::pair<std::uint64_t, std::uint32_t>> edges; // (low << 32 | high, 1 when low -> high)
        for (const std::uint32_t t : local)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = coarse.triangles[t][k], b = coarse.triangles[t][(k + 1) % 3];
                if (owner[a] != none || owner[b] != none)
                    edges.emplace_back(std::uint64_t{std::min(a, b)} << 32 | std::max(a, b), a < b);
            }
        std::sort(edges.begin(), edges.end());
        bool clash = false;
        for (std::size_t i = 0; i < edges.size();) {
            std::size_t j = i;
            while (j < edges.size() && edges[j].first == edges[i].first) ++j;
            if (j - i > 2 || (j - i == 2 && edges[i].second == edges[i + 1].second)) {
                clash = true;
                for (const auto v :
                     {static_cast<std::uint32_t>(edges[i].first >> 32), static_cast<std::uint32_t>(edges[i].first)})
                    if (owner[v] != none) kept[owner[v]] = 0;
            }
            i = j;
        }
        if (!clash) {
            report.joined = static_cast<std::size_t>(std::count(kept.begin(), kept.end(), 1));
            // A fine border edge from a moved vertex to one that stayed, still open, can lie
            // across two planes of the seam (at a corner of the refined cells): seam_edges below
            // would not see it, so it is counted here.
            for (const SeamEdge& e : fine_seam) {
                const std::uint32_t a = index[e.a], b = index[e.b];
                if (owner[a] == none && owner[b] == none) continue;
                const std::uint64_t key = std::uint64_t{std::min(a, b)} << 32 | std::max(a, b);
                const auto [lo, hi] = std::equal_range(edges.begin(), edges.end(), std::pair{key, std::uint32_t{0}},
                                                       [](const auto& x, const auto& y) { return x.first < y.first; });
                if (hi - lo != 1) continue;
                int planes = 0;
                for (int x = 0; x < 3; ++x) {
                    std::int64_t ka = 0, kb = 0;
                    planes +=
                        on_plane(coarse.positions[a][x], h, ka) && on_plane(coarse.positions[b][x], h, kb) && ka == kb;
                }
                if (planes != 1) report.open_after += length_of(coarse, {SeamEdge{e.face, a, b, e.triangle}});
            }
            break;
        }
        // Undone, to be made again.
        coarse.positions.resize(first);
        if (!coarse.colors.empty()) coarse.colors.resize(first);
        if (!coarse.normals.empty()) coarse.normals.resize(first);
        coarse.triangles.resize(coarse_triangles);
        // In reverse: a triangle split twice (on two border edges) was recorded twice, first as it was.
        for (auto it = split_from.rbegin(); it != split_from.rend(); ++it) coarse.triangles[it->first] = it->second;
        fine.positions = thin.positions;
    }
    remove_unused_vertices(coarse);
    report.open_after += length_of(coarse, seam_edges(coarse, grid, fine_cells, near));
    return report;
}

} // namespace lasmesh
