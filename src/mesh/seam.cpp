// SPDX-License-Identifier: Apache-2.0
// append_joined: the seam between the coarse mesh and the fine mesh of the thin parts, joined
// on the cell faces where they meet (Shu, Zhou & Kankanhalli 1995's crack patching).
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

// A fine chain laid onto a coarse segment P -> Q of coarse triangle `triangle`. The chain runs
// from Q's cell edge towards P's: its end on Q's edge becomes Q, its end on P's edge (when it
// reaches it) P, and its vertices in between go onto the segment. A chain that ends inside the
// face (at a hole of the fine sheet) or on another cell edge is laid from the end that matches
// as far as it follows the segment: there the seam is joined in part.
struct Match {
    std::uint32_t triangle, p, q;
    std::uint32_t at_q = none, at_p = none; // the fine vertices that become Q and P, if any
    std::vector<std::uint32_t> inner;       // the fine vertices laid onto the segment, from Q's end to P's
    std::vector<V3> onto;                   // their places on it
};

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

// The coarse segment a chain matches on its face, laid out, or nothing: both its ends on the
// segment's cell edges (Q's first), or one of them, and then at least one vertex laid.
std::optional<Match> match_chain(const Mesh& coarse, const Mesh& fine, const std::vector<SeamEdge>& segments,
                                 const std::vector<std::uint32_t>& chain, double h) {
    const LatticeEdge from = lattice_edge(fine, chain.front(), h), to = lattice_edge(fine, chain.back(), h);
    if (from == to) return std::nullopt;
    for (std::size_t i = 1; i + 1 < chain.size(); ++i)
        if (lattice_edge(fine, chain[i], h).axis != 3) return std::nullopt;
    // The segment whose Q lies on the chain's first cell edge, or whose P on its last.
    const SeamEdge* found = nullptr;
    bool at_q = false, at_p = false;
    for (const SeamEdge& s : segments) {
        const bool q = from.axis != 3 && lattice_edge(coarse, s.b, h) == from;
        const bool p = to.axis != 3 && lattice_edge(coarse, s.a, h) == to;
        if (!q && !p) continue;
        if (found) return std::nullopt;
        found = &s, at_q = q, at_p = p;
    }
    if (!found) return std::nullopt;
    Match m{found->triangle, found->a, found->b, none, none, {}, {}};
    const V3 p = position(coarse, m.p), q = position(coarse, m.q);
    const V3 pq{q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    const double length2 = pq[0] * pq[0] + pq[1] * pq[1] + pq[2] * pq[2];
    if (!(length2 > 0)) return std::nullopt;
    // Where a vertex goes on the segment: its parameter from P (0) to Q (1), or nothing when it
    // is too far from it (more than half a cell) or past its ends.
    const auto laid = [&](std::uint32_t v) -> std::optional<std::pair<double, V3>> {
        const V3 x = position(fine, v);
        const double s = ((x[0] - p[0]) * pq[0] + (x[1] - p[1]) * pq[1] + (x[2] - p[2]) * pq[2]) / length2;
        if (!(s > 1e-3 && s < 1 - 1e-3)) return std::nullopt;
        const V3 onto{p[0] + s * pq[0], p[1] + s * pq[1], p[2] + s * pq[2]};
        const V3 d{x[0] - onto[0], x[1] - onto[1], x[2] - onto[2]};
        if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > h * h / 4) return std::nullopt;
        return std::pair{s, onto};
    };
    const std::size_t n = chain.size();
    if (at_q && at_p) { // the whole chain, its parameters falling from Q to P
        m.at_q = chain.front(), m.at_p = chain.back();
        double last = 1;
        for (std::size_t i = 1; i + 1 < n; ++i) {
            const auto at = laid(chain[i]);
            if (!at || !(at->first < last - 1e-3)) return std::nullopt;
            last = at->first;
            m.inner.push_back(chain[i]), m.onto.push_back(at->second);
        }
        return m;
    }
    // One end: from it, as long as the vertices follow the segment (the far end too when it lies
    // inside the face, at a hole; on another cell edge it stays).
    if (at_q) {
        m.at_q = chain.front();
        double last = 1;
        for (std::size_t i = 1; i + (to.axis == 3 ? 0 : 1) < n; ++i) {
            const auto at = laid(chain[i]);
            if (!at || !(at->first < last - 1e-3)) break;
            last = at->first;
            m.inner.push_back(chain[i]), m.onto.push_back(at->second);
        }
    } else {
        m.at_p = chain.back();
        double last = 0;
        for (std::size_t i = n - 1; i-- > (from.axis == 3 ? 0 : 1);) {
            const auto at = laid(chain[i]);
            if (!at || !(at->first > last + 1e-3)) break;
            last = at->first;
            m.inner.insert(m.inner.begin(), chain[i]), m.onto.insert(m.onto.begin(), at->second);
        }
    }
    if (m.inner.empty()) return std::nullopt;
    return m;
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
    // Face by face: the fine chains matched to the coarse segments.
    std::vector<Match> matches;
    std::vector<SeamEdge> segments, pieces;
    for_each_face(coarse_seam, fine_seam, segments, pieces, [&] {
        ++report.faces;
        for (const std::vector<std::uint32_t>& chain : chains_of(pieces))
            if (auto m = match_chain(coarse, fine, segments, chain, h)) matches.push_back(std::move(*m));
    });
    // Each coarse triangle split once, each fine end on one coarse vertex and the other way round;
    // then no fine triangle turned over by the moves. What fails is left open.
    std::vector<char> kept(matches.size(), 1);
    const auto drop_shared = [&](auto key_of) {
        std::vector<std::tuple<std::uint32_t, std::uint32_t, std::size_t>> keys; // (key, partner, match)
        for (std::size_t i = 0; i < matches.size(); ++i)
            if (kept[i])
                for (const auto& [key, partner] : key_of(matches[i])) keys.emplace_back(key, partner, i);
        std::sort(keys.begin(), keys.end());
        for (std::size_t i = 0; i < keys.size();) {
            std::size_t j = i;
            bool shared = false;
            while (j < keys.size() && std::get<0>(keys[j]) == std::get<0>(keys[i]))
                shared = shared || std::get<1>(keys[j]) != std::get<1>(keys[i]), ++j;
            if (shared)
                for (std::size_t k = i; k < j; ++k) kept[std::get<2>(keys[k])] = 0;
            i = j;
        }
    };
    using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
    {
        // A coarse triangle is split once: by one chain, on one edge.
        std::vector<std::pair<std::uint32_t, std::size_t>> split; // (triangle, match)
        for (std::size_t i = 0; i < matches.size(); ++i) split.emplace_back(matches[i].triangle, i);
        std::sort(split.begin(), split.end());
        for (std::size_t i = 0; i + 1 < split.size(); ++i)
            if (split[i].first == split[i + 1].first) kept[split[i].second] = kept[split[i + 1].second] = 0;
    }
    const auto welds = [](const Match& m, bool fine_first) {
        Pairs pairs;
        for (const auto& [f, c] : {std::pair{m.at_q, m.q}, std::pair{m.at_p, m.p}})
            if (f != none) pairs.push_back(fine_first ? std::pair{f, c} : std::pair{c, f});
        return pairs;
    };
    drop_shared([&](const Match& m) { return welds(m, true); });
    drop_shared([&](const Match& m) { return welds(m, false); });
    std::vector<std::vector<std::uint32_t>> fine_triangles_of(fine.positions.size());
    for (std::uint32_t t = 0; t < fine.triangles.size(); ++t)
        for (const std::uint32_t v : fine.triangles[t]) fine_triangles_of[v].push_back(t);
    std::vector<V3> moved_to(fine.positions.size());
    std::vector<std::uint32_t> moved_by(fine.positions.size(), none);
    for (bool turned = true; turned;) {
        std::fill(moved_by.begin(), moved_by.end(), none);
        for (std::uint32_t i = 0; i < matches.size(); ++i) {
            if (!kept[i]) continue;
            const Match& m = matches[i];
            if (m.at_q != none) moved_to[m.at_q] = position(coarse, m.q), moved_by[m.at_q] = i;
            if (m.at_p != none) moved_to[m.at_p] = position(coarse, m.p), moved_by[m.at_p] = i;
            for (std::size_t k = 0; k < m.inner.size(); ++k) moved_to[m.inner[k]] = m.onto[k], moved_by[m.inner[k]] = i;
        }
        turned = false;
        for (std::uint32_t v = 0; v < fine.positions.size(); ++v) {
            if (moved_by[v] == none) continue;
            for (const std::uint32_t t : fine_triangles_of[v]) {
                std::array<V3, 3> was{}, now{};
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t w = fine.triangles[t][k];
                    was[k] = now[k] = position(fine, w);
                    if (moved_by[w] != none) now[k] = moved_to[w];
                }
                const V3 a = normal_of(was), b = normal_of(now);
                const double along = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
                if (along > 0 &&
                    b[0] * b[0] + b[1] * b[1] + b[2] * b[2] > 1e-6 * (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]))
                    continue;
                for (const std::uint32_t w : fine.triangles[t])
                    if (moved_by[w] != none) kept[moved_by[w]] = 0;
                turned = true;
            }
        }
    }
    // The fine mesh after the coarse one, its matched ends on the coarse vertices.
    const auto first = static_cast<std::uint32_t>(coarse.positions.size());
    std::vector<std::uint32_t> index(fine.positions.size());
    for (std::uint32_t v = 0; v < fine.positions.size(); ++v) index[v] = first + v;
    for (std::uint32_t i = 0; i < matches.size(); ++i) {
        if (!kept[i]) continue;
        const Match& m = matches[i];
        if (m.at_q != none) index[m.at_q] = m.q;
        if (m.at_p != none) index[m.at_p] = m.p;
        for (std::size_t k = 0; k < m.inner.size(); ++k)
            for (int a = 0; a < 3; ++a) fine.positions[m.inner[k]][a] = static_cast<float>(m.onto[k][a]);
    }
    std::vector<std::array<std::uint32_t, 3>> triangles;
    triangles.swap(fine.triangles);
    append_mesh(coarse, fine);
    for (auto t : triangles) {
        for (std::uint32_t& v : t) v = index[v];
        coarse.triangles.push_back(t);
    }
    // Each matched coarse triangle (P, Q, R) becomes a fan from R over P, the laid vertices from
    // P's end, and Q.
    for (std::uint32_t i = 0; i < matches.size(); ++i) {
        if (!kept[i]) continue;
        const Match& m = matches[i];
        const std::array<std::uint32_t, 3> t = coarse.triangles[m.triangle];
        int e = 0;
        while (!(t[e] == m.p && t[(e + 1) % 3] == m.q)) ++e;
        const std::uint32_t r = t[(e + 2) % 3];
        std::vector<std::uint32_t> along{m.p};
        for (std::size_t k = m.inner.size(); k-- > 0;) along.push_back(index[m.inner[k]]);
        along.push_back(m.q);
        coarse.triangles[m.triangle] = {along[0], along[1], r};
        for (std::size_t k = 1; k + 1 < along.size(); ++k) coarse.triangles.push_back({along[k], along[k + 1], r});
        ++report.joined;
    }
    remove_unused_vertices(coarse);
    return report;
}

} // namespace lasmesh
