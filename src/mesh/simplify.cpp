// SPDX-License-Identifier: Apache-2.0
// Simplification to an error bound by half-edge collapses (a vertex moves onto a neighbour, so
// kept vertices keep their position, colour and normal), ordered by the quadric error metric of
// Garland & Heckbert 1997, "Surface simplification using quadric error metrics" (SIGGRAPH 97):
// each vertex carries the sum of the planes of the original faces merged into it, weighted by
// area, and the cheapest collapse goes first. Our own implementation; on top of the paper:
//
// - a bound, not a target: every face carries a bound on how far the original surface it stands
//   for may be from it, both ways (star_errors: the two stars around a collapse compared along
//   their normal, after Cohen, Manocha and Olano 1997, the steps of a face's history added, signed
//   along the face's normal so that steps up and down do not add up), and no collapse may take that
//   past the bound, so every point of the result lies within the bound
//   of the original surface and every point of the original within it of the result; no piece
//   vanishes; among the allowed collapses of a vertex, the one adding the least error is made;
// - no face turns over: a collapse is refused when a new face's normal points away from the
//   original surface (the original normals of its three vertices) or turns far from the face it
//   replaces, or when it has (next to) no area;
// - no new non-manifold edges: the link condition (Dey, Edelsbrunner et al. 1999) with open
//   borders closed by a virtual vertex, and vertices where a sheet touches itself never move;
//   border vertices move only along their border, and no farther from it than the bound;
// - in parallel and deterministic: the mesh is cut into blocks by a fixed grid (its edge a
//   multiple of the mean edge length), each block is simplified by one thread with the vertices
//   it shares with other blocks held, and further passes with the grid shifted by half a block
//   free those. Blocks never share what they write, so any thread count gives the same bytes.
#include "lasmesh/simplify.hpp"
#include "mesh/mesh_edit.hpp"

#include "lasmesh/normals.hpp"
#include "measure/mesh_distance.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

namespace lasmesh {

namespace {

using Face = std::array<std::uint32_t, 3>;
using V3 = std::array<double, 3>;

V3 sub(const V3& a, const V3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
V3 cross(const V3& a, const V3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V3& a, const V3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
double norm(const V3& a) {
    return std::sqrt(dot(a, a));
}

// A symmetric 4x4 matrix: the sum of the squared distances to planes, p^T Q p with p = (x, y, z, 1).
struct Quadric {
    double xx, xy, xz, xw, yy, yz, yw, zz, zw, ww; // Quadric{} is zero
    void add_plane(const V3& n, double d, double weight) {
        xx += weight * n[0] * n[0], xy += weight * n[0] * n[1], xz += weight * n[0] * n[2], xw += weight * n[0] * d;
        yy += weight * n[1] * n[1], yz += weight * n[1] * n[2], yw += weight * n[1] * d;
        zz += weight * n[2] * n[2], zw += weight * n[2] * d, ww += weight * d * d;
    }
    void add(const Quadric& q) {
        xx += q.xx, xy += q.xy, xz += q.xz, xw += q.xw, yy += q.yy, yz += q.yz, yw += q.yw, zz += q.zz, zw += q.zw,
            ww += q.ww;
    }
    double at(const V3& p) const {
        const double x = p[0], y = p[1], z = p[2];
        return x * (xx * x + 2 * (xy * y + xz * z + xw)) + y * (yy * y + 2 * (yz * z + yw)) + z * (zz * z + 2 * zw) +
               ww;
    }
};

void unit_normal(V3& n) {
    const double length = norm(n);
    if (length > 0) n = {n[0] / length, n[1] / length, n[2] / length};
}

// Distance from p to the segment ab.
double segment_distance(const V3& p, const V3& a, const V3& b) {
    const V3 ab = sub(b, a), ap = sub(p, a);
    const double len2 = dot(ab, ab);
    const double t = len2 > 0 ? std::clamp(dot(ap, ab) / len2, 0.0, 1.0) : 0.0;
    return norm(sub(ap, {ab[0] * t, ab[1] * t, ab[2] * t}));
}

// The nearest float at or above `value`: a face's error is a bound, and must not round down.
float float_at_least(double value) {
    const float f = static_cast<float>(value);
    return static_cast<double>(f) < value ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// The nearest float at or below `value`.
float float_at_most(double value) {
    const float f = static_cast<float>(value);
    return static_cast<double>(f) > value ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

// How far the original surface a face stands for may be from it, two ways (both bounds hold):
// `total`, the sum of the largest steps of its history; and the points' offsets from the face
// split along its normal, within [below, above], and across it, within `across`. Each step of a
// collapse moves points along one direction; split along the face's normal, steps up and down
// cancel (a noisy flat area is flattened without the bound filling up), and only the turn of the
// normal between steps adds across.
struct FaceError {
    float below, above, across, total; // FaceError{} is zero
    std::array<float, 3> axis;         // the direction of its last step (a unit vector), or zero
};

double bound(const FaceError& e) {
    return std::min(double(e.total), std::max(-double(e.below), double(e.above)) + double(e.across));
}

// A point as seen along a direction n: its coordinates across n, and its height along it.
struct Seen {
    double x, y, h;
};

// Twice the signed area of the triangle a, b, c across n (positive: counter-clockwise about n).
double cross2(const Seen& a, const Seen& b, const Seen& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// A direction's angle around the origin, as a number from -2 to 2 that grows with it (cheaper
// than atan2; only the order matters).
double pseudo_angle(const Seen& d) {
    const double sum = std::abs(d.x) + std::abs(d.y);
    if (!(sum > 0)) return 0;
    return std::copysign(1 - d.x / sum, d.y);
}

// The range of directions from the origin a triangle (not holding the origin) spans: its
// vertices' pseudo-angles, from the first to the last counter-clockwise, the end past the start
// (4 added when it wraps).
std::pair<double, double> directions(const Seen& a, const Seen& b, const Seen& c) {
    std::array<double, 3> p{pseudo_angle(a), pseudo_angle(b), pseudo_angle(c)};
    std::sort(p.begin(), p.end());
    // The largest gap between consecutive directions (round the circle) is outside the range.
    const std::array<double, 3> gap{p[1] - p[0], p[2] - p[1], p[0] + 4 - p[2]};
    const int widest = int(std::max_element(gap.begin(), gap.end()) - gap.begin());
    if (widest == 2) return {p[0], p[2]};
    if (widest == 0) return {p[1], p[0] + 4};
    return {p[2], p[1] + 4};
}

// The sector from a to b counter-clockwise (less than half a turn) as pseudo-angles, the end
// past the start (4 added when it wraps).
std::pair<double, double> sector(const Seen& a, const Seen& b) {
    const double start = pseudo_angle(a);
    const double end = pseudo_angle(b);
    return {start, end <= start ? end + 4 : end};
}

// Whether the range of directions [from, to] (as `directions` gives it) and the sector [start,
// end] (as `sector` gives it) share more than a boundary.
bool arcs_overlap(double from, double to, double start, double end) {
    constexpr double margin = 1e-12;
    for (const double shift : {-4.0, 0.0, 4.0})
        if (start + shift < to - margin && from < end + shift - margin) return true;
    return false;
}

// Limits on a new face: its normal against the original surface's at its corners, and against
// the face it replaces (cosines). A face standing more than ~78 degrees off either is refused.
constexpr double min_cos_original = 0.2;
constexpr double min_cos_replaced = 0.2;
// A face with a cross product below this fraction of its longest edge squared has no area.
constexpr double min_area_ratio = 1e-4;

// Per vertex: the sum of the planes of its faces, their area, and its faces' normals.
struct PlaneSums { // PlaneSums{} is zero; `new PlaneSums[n]` leaves it to be set
    Quadric quadric;
    double weight;
    V3 reference; // a unit vector once all faces are in
};

// A face's plane as a quadric weighted by its area, and its normal as long as twice its area.
struct Plane {
    Quadric quadric;
    double area;
    V3 normal;
    void add_to(PlaneSums& p) const {
        p.quadric.add(quadric), p.weight += area;
        for (int a = 0; a < 3; ++a) p.reference[a] += normal[a];
    }
};

Plane face_plane(const std::vector<std::array<float, 3>>& position, const Face& t) {
    const auto at = [&](std::uint32_t v) { return V3{position[v][0], position[v][1], position[v][2]}; };
    const V3 a = at(t[0]);
    Plane p{{}, 0, cross(sub(at(t[1]), a), sub(at(t[2]), a))};
    const double length = norm(p.normal);
    if (!(length > 0)) return p;
    const V3 unit{p.normal[0] / length, p.normal[1] / length, p.normal[2] / length};
    p.area = length / 2;
    p.quadric.add_plane(unit, -dot(unit, a), p.area);
    return p;
}

// What the blocks share. Each block writes only its own faces and the vertices no other block
// touches, so blocks run in any order, at once, with the same result.
struct Shared {
    const std::vector<std::array<float, 3>>& position;
    std::vector<Face>& faces; // current faces
    // Per vertex, where its quadric, area and original unit normal are in `stored` (after the
    // first pass: every vertex left; during it, the vertices blocks share). The first pass gives
    // each block a range of slots for the vertices only it has, so they go straight there; the
    // slots of the vertices it removes are never written, and their pages are never touched.
    std::vector<std::uint32_t> slot;
    std::unique_ptr<PlaneSums[]> stored;
    std::vector<char> face_alive;
    std::vector<FaceError> face_error; // how far the original surface it stands for may be
    std::vector<char> locked;          // vertices that never move
    std::vector<char> outside;         // per vertex, this pass: faces in other blocks, or in none
    double bound = 0;
};

// One thread's workspace: loads a block of faces (in local numbers, with the faces around each
// vertex) and simplifies it. Reused from block to block, so its buffers are allocated once.
class Block {
  public:
    explicit Block(Shared& s) : s_(s) {}

    void load(const std::uint32_t* face_ids, std::size_t count) {
        // Local numbers through a hash table sized for the block (open addressing, linear
        // probing): a table per thread over every vertex of the mesh took 8 bytes a vertex a
        // thread (0.4 GB on 2 threads for 25M vertices).
        int bits = 4;
        while ((std::size_t{1} << bits) < 6 * count) ++bits;
        const std::size_t mask = (std::size_t{1} << bits) - 1;
        table_.assign(mask + 1, {empty_slot, 0});
        global_face_.assign(face_ids, face_ids + count);
        global_.clear();
        face_.resize(count);
        for (std::size_t f = 0; f < count; ++f)
            for (int k = 0; k < 3; ++k) { // local numbers in order of first use: the same in any thread
                const std::uint32_t g = s_.faces[global_face_[f]][k];
                std::size_t h = static_cast<std::size_t>((std::uint64_t{g} * 0x9E3779B97F4A7C15ull) >> (64 - bits));
                while (table_[h].first != empty_slot && table_[h].first != g) h = (h + 1) & mask;
                if (table_[h].first == empty_slot) table_[h] = {g, std::uint32_t(global_.size())}, global_.push_back(g);
                face_[f][k] = table_[h].second;
            }
        const std::size_t n = global_.size();
        position_.resize(n);
        for (std::size_t v = 0; v < n; ++v) {
            const auto& p = s_.position[global_[v]];
            position_[v] = {p[0], p[1], p[2]};
        }
        face_alive_.assign(count, 1);
        size_.assign(n, 0);
        for (const Face& f : face_)
            for (const std::uint32_t v : f) ++size_[v];
        begin_.resize(n), capacity_.resize(n);
        std::uint32_t at = 0;
        for (std::size_t v = 0; v < n; ++v)
            begin_[v] = at, capacity_[v] = size_[v] + 4, at += capacity_[v], size_[v] = 0;
        pool_.resize(at);
        for (std::uint32_t f = 0; f < count; ++f)
            for (const std::uint32_t v : face_[f]) pool_[begin_[v] + size_[v]++] = f;
        tag_.assign(n, 0), slot_.assign(n, 0), ring_.assign(n, 0);
        tag_now_ = ring_now_ = 0;
    }

    // Sums the planes (quadric, area) and area-weighted normals of the block's faces per vertex.
    void sum_planes() {
        const std::size_t n = global_.size();
        quadric_.assign(n, Quadric{}), weight_.assign(n, 0), reference_.assign(n, {0, 0, 0});
        for (std::size_t f = 0; f < face_.size(); ++f) {
            const Plane plane = face_plane(s_.position, s_.faces[global_face_[f]]);
            for (const std::uint32_t v : face_[f]) {
                quadric_[v].add(plane.quadric), weight_[v] += plane.area;
                for (int a = 0; a < 3; ++a) reference_[v][a] += plane.normal[a];
            }
        }
    }

    // Simplifies the block. First pass: the planes come from the block's faces (the shared
    // vertices' from s_.stored), and the vertices only this block has that are left go to
    // s_.stored from `first_slot` on; later passes: from and back to s_.stored.
    void run(bool first_pass, std::uint32_t first_slot) {
        const std::size_t n = global_.size();
        movable_.assign(n, 0), target_.assign(n, 0), stamp_.assign(n, 0), alive_.assign(n, 1), queued_.assign(n, 0);
        interior_.assign(n, 0);
        for (std::uint32_t v = 0; v < n; ++v) {
            const std::uint32_t g = global_[v];
            if (s_.outside[g]) continue; // shares faces with another block, or with none this pass: held
            interior_[v] = 1;
            if (!simple_fan(v)) continue; // a sheet touching itself here, or worse
            target_[v] = 1;
            movable_[v] = !s_.locked[g];
        }
        if (first_pass) {
            sum_planes();
            for (std::uint32_t v = 0; v < n; ++v) {
                const std::uint32_t g = global_[v];
                if (interior_[v])
                    unit_normal(reference_[v]);
                else
                    reference_[v] = s_.stored[s_.slot[g]].reference;
            }
        } else {
            quadric_.resize(n), weight_.resize(n), reference_.resize(n);
            for (std::uint32_t v = 0; v < n; ++v) {
                const PlaneSums& p = s_.stored[s_.slot[global_[v]]];
                quadric_[v] = p.quadric, weight_[v] = p.weight, reference_[v] = p.reference;
            }
        }
        heap_.clear();
        face_error_.resize(face_.size());
        for (std::size_t f = 0; f < face_.size(); ++f) face_error_[f] = s_.face_error[global_face_[f]];
        for (std::uint32_t v = 0; v < global_.size(); ++v) // the first costs, heaped at once
            if (movable_[v]) push(v, false);
        std::make_heap(heap_.begin(), heap_.end());
        while (!heap_.empty()) {
            std::pop_heap(heap_.begin(), heap_.end());
            const Entry e = heap_.back();
            heap_.pop_back();
            if (!alive_[e.vertex] || e.stamp != stamp_[e.vertex]) continue;
            try_collapse(e.vertex, e.cost);
        }
        for (std::size_t f = 0; f < face_.size(); ++f) {
            const std::uint32_t g = global_face_[f];
            s_.face_alive[g] = face_alive_[f];
            s_.face_error[g] = face_error_[f];
            for (int k = 0; k < 3; ++k) s_.faces[g][k] = global_[face_[f][k]];
        }
        for (std::uint32_t v = 0; v < n; ++v) {
            const std::uint32_t g = global_[v];
            if (!interior_[v] || !alive_[v]) continue;
            if (first_pass)
                s_.slot[g] = first_slot, s_.stored[first_slot++] = {quadric_[v], weight_[v], reference_[v]};
            else if (target_[v])
                s_.stored[s_.slot[g]].quadric = quadric_[v], s_.stored[s_.slot[g]].weight = weight_[v];
        }
    }

  private:
    struct Entry {
        double cost;
        std::uint32_t vertex, stamp;
        bool operator<(const Entry& o) const { return cost != o.cost ? cost > o.cost : vertex > o.vertex; }
    };
    // A collapse of u onto `vertex`: its order, then the error its faces would carry; where its
    // faces' errors are kept.
    struct Candidate {
        double cost;
        std::uint32_t vertex, split_at;
    };
    struct Neighbour {
        std::uint32_t vertex, uses;
        Neighbour() {} // left unset by resize: neighbours() fills what it keeps
        Neighbour(std::uint32_t v, std::uint32_t n) : vertex(v), uses(n) {}
    };

    const V3& pos(std::uint32_t v) const { return position_[v]; }
    const Quadric& quadric(std::uint32_t v) const { return quadric_[v]; }
    double weight(std::uint32_t v) const { return weight_[v]; }
    const std::uint32_t* fan(std::uint32_t v) const { return pool_.data() + begin_[v]; }

    // The vertices around v and how many of v's faces use the edge to each: 1 on an open border.
    void neighbours(std::uint32_t v, std::vector<Neighbour>& out) {
        out.resize(2 * size_[v] + 2); // at most two new neighbours a face
        Neighbour* next = out.data();
        ++tag_now_;
        const std::uint32_t* around = fan(v);
        for (std::uint32_t i = 0; i < size_[v]; ++i)
            for (const std::uint32_t w : face_[around[i]]) {
                if (w == v) continue;
                if (tag_[w] != tag_now_)
                    tag_[w] = tag_now_, slot_[w] = std::uint32_t(next - out.data()), *next++ = {w, 1};
                else
                    ++out[slot_[w]].uses;
            }
        out.resize(std::size_t(next - out.data()));
    }

    // One fan of faces around v, joined edge to edge, open (two border edges) or closed: the
    // edges opposite v join all of v's neighbours into one piece.
    bool simple_fan(std::uint32_t v) {
        neighbours(v, around_);
        std::size_t border = 0;
        for (const Neighbour& n : around_) {
            if (n.uses > 2) return false;
            border += n.uses == 1;
        }
        if (border != 0 && border != 2) return false;
        parent_.resize(around_.size());
        for (std::uint32_t i = 0; i < parent_.size(); ++i) parent_[i] = i;
        const auto root = [&](std::uint32_t i) {
            while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
            return i;
        };
        std::size_t pieces = around_.size();
        for (std::uint32_t i = 0; i < size_[v]; ++i) {
            const Face& f = face_[fan(v)[i]];
            if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) return false;
            const int at = f[0] == v ? 0 : f[1] == v ? 1 : 2;
            const std::uint32_t a = root(slot_[f[(at + 1) % 3]]), b = root(slot_[f[(at + 2) % 3]]);
            if (a != b) parent_[a] = b, --pieces;
        }
        return pieces == 1;
    }

    // The largest error u's faces carry.
    double carried(std::uint32_t u) const {
        double most = 0;
        for (std::uint32_t i = 0; i < size_[u]; ++i) most = std::max(most, bound(face_error_[fan(u)[i]]));
        return most;
    }

    // The order of collapses: the mean squared distance of u and v's original planes from v
    // (the quadric error metric), plus the square of the error u's faces carry already (`carried`):
    // where the bound is mostly spent, collapses wait, so it goes further elsewhere first (the
    // unit test's deck at half a cell: 4,036 triangles, against 4,606 by the quadric alone).
    double cost(std::uint32_t u, std::uint32_t v, double carried) const {
        const double w = weight(u) + weight(v);
        const V3& p = pos(v);
        const double q = quadric(u).at(p) + quadric(v).at(p);
        return (w > 0 ? std::max(0.0, q) / w : 0.0) + carried * carried;
    }

    // Queues u at the cost of its cheapest collapse, if within the bound.
    void push(std::uint32_t u, bool heap = true) {
        neighbours(u, around_);
        push(u, around_, heap);
    }
    void push(std::uint32_t u, const std::vector<Neighbour>& around, bool heap = true) {
        ++stamp_[u];
        double best = std::numeric_limits<double>::infinity();
        const double spent = carried(u);
        for (const Neighbour& n : around)
            if (target_[n.vertex]) best = std::min(best, cost(u, n.vertex, spent));
        queued_[u] = best <= s_.bound * s_.bound;
        if (!queued_[u]) return;
        heap_.push_back({best, u, stamp_[u]});
        if (heap) std::push_heap(heap_.begin(), heap_.end());
    }

    // u came off the queue at `queued_cost`. Its neighbours' collapses since may have made its
    // own dearer: then it goes back at the new cost. Otherwise the cheapest allowed collapse is
    // made; with none allowed, u waits until its neighbourhood changes.
    void try_collapse(std::uint32_t u, double queued_cost) {
        queued_[u] = 0;
        neighbours(u, around_u_);
        candidates_.clear();
        const double spent = carried(u);
        for (const Neighbour& n : around_u_)
            if (target_[n.vertex]) {
                const double c = cost(u, n.vertex, spent);
                if (c <= s_.bound * s_.bound) candidates_.push_back({c, n.vertex, 0});
            }
        if (candidates_.empty()) return;
        std::sort(candidates_.begin(), candidates_.end(), [](const Candidate& a, const Candidate& b) {
            return a.cost != b.cost ? a.cost < b.cost : a.vertex < b.vertex;
        });
        if (candidates_[0].cost > queued_cost * (1 + 1e-6) + 1e-30) {
            ++stamp_[u];
            queued_[u] = 1;
            heap_.push_back({candidates_[0].cost, u, stamp_[u]});
            std::push_heap(heap_.begin(), heap_.end());
            return;
        }
        // Of the allowed collapses, the one whose faces would carry the least error (ties: the
        // cheapest, as sorted): the bound lasts longer. The geometry first, the topology (which
        // needs v's neighbours) only for the collapse chosen.
        // No collapse carries less than u's faces do already (the new faces cover the old ones):
        // one that adds nothing is the best, and the rest need no look.
        star_seen_ = false; // u's star is seen at the first collapse that needs it
        // Each allowed collapse's new errors are kept (from `split_at` on in tried_split_) for
        // the collapse made.
        tried_split_.clear();
        for (std::size_t i = 0; i < candidates_.size(); ++i) {
            double error = 0;
            Candidate& c = candidates_[i];
            c.cost = geometry_allows(u, c.vertex, error) ? error : std::numeric_limits<double>::infinity();
            c.split_at = std::uint32_t(tried_split_.size());
            if (c.cost != std::numeric_limits<double>::infinity())
                tried_split_.insert(tried_split_.end(), new_split_.begin(), new_split_.end());
            if (c.cost <= spent) {
                candidates_.resize(i + 1);
                break;
            }
        }
        std::stable_sort(candidates_.begin(), candidates_.end(),
                         [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
        for (const Candidate& c : candidates_) {
            if (c.cost == std::numeric_limits<double>::infinity()) return;
            if (!topology_allows(u, c.vertex)) continue;
            return collapse(u, c.vertex, tried_split_.data() + c.split_at);
        }
    }

    // u's star as seen along n, the direction of its faces' summed normals, the same for every v
    // u may move onto (star_errors), so seen once a try: the plane across n (u at its origin),
    // per old face its corners there, its errors and the terms of its split turned onto n, and
    // the link's vertices. False when n is zero or a face is
    // folded over as seen along it.
    //
    // A point's offset from an old face i, a n_i + L (a in [below, above], |L| <= across, L
    // across n_i), is a c + L.n along n (|L.n| <= across s, c = n_i.n, s = sqrt(1 - c^2)) and at
    // most |a| s + across across it.
    bool see_star(std::uint32_t u) {
        V3 n{0, 0, 0};
        for (std::uint32_t i = 0; i < size_[u]; ++i) {
            const Face& f = face_[fan(u)[i]];
            const V3 c = cross(sub(pos(f[1]), pos(f[0])), sub(pos(f[2]), pos(f[0])));
            for (int a = 0; a < 3; ++a) n[a] += c[a];
        }
        const double n_length = norm(n);
        if (!(n_length > 0)) return false;
        for (double& c : n) c /= n_length;
        // Two directions across n: the plane the stars are seen in, u at its origin.
        V3 t1 = cross(n, std::abs(n[0]) < 0.6 ? V3{1, 0, 0} : V3{0, 1, 0});
        const double t1_length = norm(t1);
        for (double& c : t1) c /= t1_length;
        star_origin_ = pos(u), star_n_ = n, star_t1_ = t1, star_t2_ = cross(n, t1);
        old_fan_.clear(), old_ends_.clear(), old_scale_.clear(), old_error_.clear(), old_turned_.clear();
        old_link_.clear(), link_.clear();
        const auto link_of = [&](std::uint32_t vertex, const Seen& at) {
            std::uint32_t l = 0;
            while (l < link_.size() && link_[l].vertex != vertex) ++l;
            if (l == link_.size()) link_.push_back({vertex, at, 0});
            return l;
        };
        const Seen su{0, 0, 0};
        for (std::uint32_t i = 0; i < size_[u]; ++i) {
            const std::uint32_t fi = fan(u)[i];
            const Face& f = face_[fi];
            const int at = f[0] == u ? 0 : f[1] == u ? 1 : 2;
            const std::uint32_t a = f[(at + 1) % 3], b = f[(at + 2) % 3];
            const Seen sa = seen(pos(a)), sb = seen(pos(b));
            const double scale = std::max({sa.x * sa.x + sa.y * sa.y, sb.x * sb.x + sb.y * sb.y, 1e-300});
            if (!(cross2(su, sa, sb) > 1e-9 * scale)) return false; // folded over, as seen along n
            old_link_.push_back({link_of(a, sa), link_of(b, sb)});
            old_fan_.push_back({sa, sb});
            old_ends_.push_back({a, b});
            old_scale_.push_back(scale);
            const FaceError& e = face_error_[fi];
            old_error_.push_back(bound(e));
            const V3 axis{e.axis[0], e.axis[1], e.axis[2]};
            const double c = std::clamp(dot(axis, n), -1.0, 1.0), sine = std::sqrt(1 - c * c);
            const double lo = std::min(e.below * c, e.above * c), hi = std::max(e.below * c, e.above * c);
            const auto [start, end] = sector(sa, sb);
            // (1e-6: the axis is kept in floats, a unit vector to about 1e-7.)
            old_turned_.push_back({lo - e.across * sine, hi + e.across * sine,
                                   std::max(-double(e.below), double(e.above)) * (sine + 1e-6) + e.across, start, end});
        }
        return true;
    }

    // A point as see_star saw u's star.
    Seen seen(const V3& p) const {
        const V3 d = sub(p, star_origin_);
        return Seen{dot(d, star_t1_), dot(d, star_t2_), dot(d, star_n_)};
    }

    // The errors the faces replacing u's would carry if u moved onto v, into new_error_ (one a
    // face of u's not on edge uv, in fan order): each new face's bound on how far the original
    // surface it stands for may be from it, both ways (every point of the one within it of the
    // other). False when the two stars cannot be compared.
    //
    // Both stars are seen from the direction n of u's faces' summed normals, where each must be a
    // height field: every face, old and new, faces n. They then cover the same polygon (u's link),
    // and a point of one surface is matched with the point of the other straight along n: the
    // composed matches of successive collapses take every point of the original surface to the
    // current one and back, and a face's error is the sum of the steps along its chain. Following
    // Cohen, Manocha and Olano, "Simplifying polygonal models using successive mappings" (IEEE
    // Visualization 1997), in the plane of the star. The height between the two stars is linear
    // on each piece of the overlay of the two fans, so over a new face it is largest at the
    // overlay's vertices in it: u, and where an edge from u crosses one of its edges from v (the
    // link's vertices are on both surfaces). A new face carries the largest error of the old faces
    // it overlaps, plus that height.
    // A border vertex u (`other` its other border neighbour, v the first) changes the polygon by
    // the sliver between the old border v-u-other and the new chord v-other, and every new face
    // then carries the old star's largest error plus the star's largest step:
    //   - u outside the new polygon: the old sliver's pieces lie within their corners' distance
    //     of the chord, u's and the crossings';
    //   - u inside it: the new sliver's pieces lie within the height between the surfaces (at u
    //     and the crossings on the border edge u-other) of the triangle v, u, other, whose every
    //     point lies within the distance from the foot of its bisector at u to the edge v-u of the
    //     old border (the farthest a point of the triangle is from its two other edges).
    bool star_errors(std::uint32_t u, std::uint32_t v, std::uint32_t other) {
        if (!star_seen_) star_visible_ = see_star(u), star_seen_ = true;
        if (!star_visible_) return false;
        const V3& pu = pos(u);
        const V3& pv = pos(v);
        const Seen su{0, 0, 0}, sv = seen(pv);
        // The new faces (v, a, b) the old faces not on edge uv become.
        new_fan_.clear(), new_link_.clear();
        for (Link& l : link_) l.new_faces = 0;
        std::size_t start = 0; // an open fan's first face, the one after its border edge u-a
        for (std::size_t i = 0; i < old_fan_.size(); ++i) {
            const auto [a, b] = old_ends_[i];
            if (other != u && (a == v || a == other)) start = i;
            if (a == v || b == v) continue; // goes
            const auto& [sa, sb] = old_fan_[i];
            if (!(cross2(sv, sa, sb) > 1e-9 * old_scale_[i])) return false;
            for (const std::uint32_t l : old_link_[i]) ++link_[l].new_faces;
            new_fan_.push_back({sa, sb});
            new_link_.push_back(old_link_[i]);
        }
        // No face left to carry the old ones' errors (u had only faces on edge uv): refused.
        if (new_fan_.empty()) return false;
        // The old fan goes round u once (a closed fan) or less (an open one): from its first edge
        // on, only a closed fan's last face reaches that edge's direction again.
        const bool border = other != u;
        const Seen& first = old_fan_[start].first;
        std::size_t reached = 0;
        for (const auto& [sa, sb] : old_fan_) reached += cross2(su, sa, first) > 0 && cross2(su, first, sb) >= 0;
        if (reached != (border ? 0 : 1)) return false;
        // Per new face: the largest height between the stars over it, at u and at the crossings.
        const std::size_t m = new_fan_.size();
        // And per old face i and new face j, the lowest and highest over the piece of the overlay
        // they share (pair_[i * m + j]; 0 at the link's vertices, which every piece has).
        step_.assign(m, 0);
        pair_below_.assign(old_fan_.size() * m, 0), pair_above_.assign(old_fan_.size() * m, 0);
        const auto at_pair = [&](std::size_t i, std::size_t j, double up) {
            pair_below_[i * m + j] = std::min(pair_below_[i * m + j], up);
            pair_above_[i * m + j] = std::max(pair_above_[i * m + j], up);
        };
        // Each edge u-a from u against each edge v-w of the new faces, once (the faces on each
        // side of either edge share what it finds).
        const auto has = [](const std::array<std::uint32_t, 2>& ends, std::uint32_t l) {
            return ends[0] == l || ends[1] == l;
        };
        for (std::uint32_t from_u = 0; from_u < link_.size(); ++from_u) {
            const Seen* a = &link_[from_u].at;
            const double v_side = a->x * sv.y - a->y * sv.x; // v's side of the line u-a
            for (std::uint32_t from_v = 0; from_v < link_.size(); ++from_v) {
                if (link_[from_v].new_faces == 0) continue;
                const Seen* w = &link_[from_v].at;
                // A proper crossing: v and w on opposite sides of u-a, u and a of v-w.
                if (v_side * (a->x * w->y - a->y * w->x) >= 0) continue;
                if (cross2(sv, *w, su) * cross2(sv, *w, *a) >= 0) continue;
                // Where: s a = v + t (w - v).
                const double fx = w->x - sv.x, fy = w->y - sv.y;
                const double det = fx * a->y - fy * a->x;
                const double s = (fx * sv.y - fy * sv.x) / det, t = (a->x * sv.y - a->y * sv.x) / det;
                const double up = sv.h + t * (w->h - sv.h) - s * a->h; // new surface over old
                for (std::size_t j = 0; j < m; ++j) {
                    if (!has(new_link_[j], from_v)) continue; // on edge v-w of new face j
                    step_[j] = std::max(step_[j], std::abs(up));
                    for (std::size_t i = 0; i < old_fan_.size(); ++i) // on edge u-a of old face i
                        if (has(old_link_[i], from_u)) at_pair(i, j, up);
                }
            }
        }
        // u over the new surface: the height there, for the faces that hold it.
        bool u_inside = false;
        holds_u_.assign(m, 0);
        for (std::size_t j = 0; j < m; ++j) {
            const auto& [sa, sb] = new_fan_[j];
            const double whole = cross2(sv, sa, sb);
            const double wv = cross2(su, sa, sb) / whole, wa = cross2(sv, su, sb) / whole, wb = 1 - wv - wa;
            constexpr double slack = -1e-9;
            if (wv < slack || wa < slack || wb < slack) continue;
            u_inside = true;
            holds_u_[j] = 1;
            const double up = wv * sv.h + wa * sa.h + wb * sb.h; // u is at height 0
            step_[j] = std::max(step_[j], std::abs(up));
            for (std::size_t i = 0; i < old_fan_.size(); ++i) at_pair(i, j, up); // u is a corner of every old face
        }
        if (!border && !u_inside) return false; // an inner u lies inside its link: numbers went astray
        // A new face carries the largest error of the old faces it overlaps. Old face i is the part
        // of the old polygon in the sector of directions from u between its edges, so a new face
        // overlaps it when their ranges of directions from u overlap (all of them when it holds u).
        // Split along the new face's normal (n: see_star turned the old splits onto it), the
        // step adds its height.
        new_error_.resize(m), new_split_.resize(m);
        for (std::size_t j = 0; j < m; ++j) {
            double carried = 0, below = 0, above = 0, across = 0;
            std::optional<std::pair<double, double>> range; // of directions from u, when the face does not hold u
            if (!holds_u_[j]) range = directions(sv, new_fan_[j].first, new_fan_[j].second);
            for (std::size_t i = 0; i < old_fan_.size(); ++i) {
                const Turned& e = old_turned_[i];
                if (range && !arcs_overlap(range->first, range->second, e.start, e.end)) continue;
                carried = std::max(carried, old_error_[i]);
                // The step along n over the piece they share adds as it is.
                below = std::min(below, e.below + pair_below_[i * m + j]);
                above = std::max(above, e.above + pair_above_[i * m + j]);
                across = std::max(across, e.across);
            }
            const double total = carried + step_[j];
            new_split_[j] = {float_at_most(below),
                             float_at_least(above),
                             float_at_least(across),
                             float_at_least(total),
                             {float(star_n_[0]), float(star_n_[1]), float(star_n_[2])}};
            new_error_[j] = bound(new_split_[j]);
        }
        if (!border) return true;
        // The sliver v, u, other: the old faces over it (u outside the new polygon) or the new
        // ones (u inside it) are matched across it, not along n.
        const Seen so = seen(pos(other));
        const V3& po = pos(other);
        const double step = *std::max_element(step_.begin(), step_.end());
        double sliver_error = 0; // the old faces over the sliver, or along the old border
        for (std::size_t i = 0; i < old_fan_.size(); ++i)
            if (overlap(sv, su, so, su, old_fan_[i].first, old_fan_[i].second))
                sliver_error = std::max(sliver_error, old_error_[i]);
        if (!u_inside) {
            // Old sliver points go to the chord v-other, an edge of the new face that was u's
            // face on the border edge u-other: it carries them.
            const double moved = std::max(step, segment_distance(pu, pv, po));
            for (std::size_t j = 0; j < m; ++j)
                if ((new_fan_[j].first.x == so.x && new_fan_[j].first.y == so.y) ||
                    (new_fan_[j].second.x == so.x && new_fan_[j].second.y == so.y))
                    new_error_[j] = std::max(new_error_[j], sliver_error + moved);
        } else {
            // New sliver points go to the old border v-u-other, edges of the old border faces.
            double border_error = 0;
            for (std::size_t i = 0; i < old_fan_.size(); ++i) {
                const auto& [sa, sb] = old_fan_[i];
                if ((sa.x == sv.x && sa.y == sv.y) || (sb.x == sv.x && sb.y == sv.y) ||
                    (sa.x == so.x && sa.y == so.y) || (sb.x == so.x && sb.y == so.y))
                    border_error = std::max(border_error, old_error_[i]);
            }
            const double uv = norm(sub(pu, pv)), uo = norm(sub(pu, po));
            const double along = uv + uo > 0 ? uv / (uv + uo) : 0.5;
            const V3 foot{pv[0] + along * (po[0] - pv[0]), pv[1] + along * (po[1] - pv[1]),
                          pv[2] + along * (po[2] - pv[2])};
            const double across = segment_distance(foot, pv, pu);
            for (std::size_t j = 0; j < m; ++j)
                if (overlap(sv, new_fan_[j].first, new_fan_[j].second, sv, so, su))
                    new_error_[j] = std::max(new_error_[j], std::max(border_error, sliver_error) + step + across);
        }
        // The sliver's points are matched across it, not along n: the split does not hold there,
        // so a border collapse's faces carry their total alone (any offset within it, either way).
        for (std::size_t j = 0; j < m; ++j) {
            const float total = float_at_least(new_error_[j]);
            new_split_[j] = {-total, total, total, total, {}};
            new_error_[j] = total;
        }
        return true;
    }

    // Whether two triangles overlap with some area, as seen along n: no edge of either has the
    // other wholly on its outer side (separating axes, for convex polygons). A triangle with no
    // area overlaps nothing.
    static bool overlap(const Seen& a0, const Seen& a1, const Seen& a2, const Seen& b0, const Seen& b1,
                        const Seen& b2) {
        const auto counter_clockwise = [](const Seen& p, const Seen& q, const Seen& r,
                                          std::array<const Seen*, 3>& out) {
            const double area = cross2(p, q, r);
            const double scale = std::max({(q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y),
                                           (r.x - p.x) * (r.x - p.x) + (r.y - p.y) * (r.y - p.y), 1e-300});
            if (std::abs(area) <= 1e-12 * scale) return false;
            out = area > 0 ? std::array<const Seen*, 3>{&p, &q, &r} : std::array<const Seen*, 3>{&p, &r, &q};
            return true;
        };
        std::array<const Seen*, 3> a{}, b{};
        if (!counter_clockwise(a0, a1, a2, a) || !counter_clockwise(b0, b1, b2, b)) return false;
        const auto separates = [](const std::array<const Seen*, 3>& t, const std::array<const Seen*, 3>& other) {
            for (int e = 0; e < 3; ++e) {
                const Seen &p = *t[e], &q = *t[(e + 1) % 3];
                const double scale = (q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y);
                bool outside = true;
                for (const Seen* x : other) outside = outside && cross2(p, q, *x) <= 1e-9 * scale;
                if (outside) return true;
            }
            return false;
        };
        return !separates(a, b) && !separates(b, a);
    }

    // Whether the surface allows u to move onto v, and the largest error its new faces would then
    // carry (star_errors has them per face). The topology is topology_allows'.
    bool geometry_allows(std::uint32_t u, std::uint32_t v, double& error) {
        // u on a border moves only along it.
        bool u_border = false;
        std::uint32_t uses_uv = 0, other_border = std::numeric_limits<std::uint32_t>::max();
        for (const Neighbour& n : around_u_) {
            if (n.uses == 1) {
                u_border = true;
                if (n.vertex != v) other_border = n.vertex;
            }
            if (n.vertex == v) uses_uv = n.uses;
        }
        if (u_border && uses_uv != 1) return false;
        // Geometry: every new face keeps some area, faces the way the original surface does at
        // its corners, and does not turn far from the face it replaces; then how far the new
        // faces may be from the original surface, within the bound.
        const V3& pv = pos(v);
        for (std::uint32_t i = 0; i < size_[u]; ++i) {
            const Face& f = face_[fan(u)[i]];
            if (f[0] == v || f[1] == v || f[2] == v) continue;
            std::array<const V3*, 3> was{&pos(f[0]), &pos(f[1]), &pos(f[2])}, now = was;
            V3 reference{0, 0, 0};
            for (int k = 0; k < 3; ++k) {
                if (f[k] == u) now[k] = &pv;
                const V3& r = reference_[f[k] == u ? v : f[k]];
                for (int a = 0; a < 3; ++a) reference[a] += r[a];
            }
            const V3 n_now = cross(sub(*now[1], *now[0]), sub(*now[2], *now[0]));
            double longest = 0;
            for (int k = 0; k < 3; ++k)
                longest = std::max(longest, dot(sub(*now[k], *now[(k + 1) % 3]), sub(*now[k], *now[(k + 1) % 3])));
            const double len_now = norm(n_now);
            if (!(len_now > min_area_ratio * longest)) return false;
            if (!(dot(n_now, reference) > min_cos_original * len_now * norm(reference))) return false;
            const V3 n_was = cross(sub(*was[1], *was[0]), sub(*was[2], *was[0]));
            const double len_was = norm(n_was);
            if (len_was > 0 && !(dot(n_now, n_was) > min_cos_replaced * len_now * len_was)) return false;
        }
        if (!star_errors(u, v, u_border ? other_border : u)) return false;
        error = *std::max_element(new_error_.begin(), new_error_.end());
        return error <= s_.bound;
    }

    bool topology_allows(std::uint32_t u, std::uint32_t v) {
        // The link condition (the vertices next to both u and v are the far corners of
        // the faces on edge uv), with open borders closed by a virtual vertex (u and v both on a
        // border joined by an inner edge: refused above, u on a border moves along it).
        neighbours(v, around_v_);
        opposite_.clear();
        for (std::uint32_t i = 0; i < size_[u]; ++i) {
            const Face& f = face_[fan(u)[i]];
            if (f[0] != v && f[1] != v && f[2] != v) continue;
            for (const std::uint32_t w : f)
                if (w != u && w != v) opposite_.push_back(w);
        }
        ++ring_now_;
        for (const Neighbour& a : around_u_) ring_[a.vertex] = ring_now_;
        std::size_t common = 0;
        for (const Neighbour& b : around_v_) common += b.vertex != u && ring_[b.vertex] == ring_now_;
        if (common != opposite_.size()) return false;
        // Pieces do not vanish: v and the far corners of the faces that go keep a face each.
        if (size_[v] <= opposite_.size()) return false;
        for (const std::uint32_t w : opposite_)
            if (size_[w] <= 1) return false;
        if (opposite_.size() == 2) { // a face (u, a, b) and a face (v, a, b): a tetrahedron would fold flat
            const auto has_both = [&](std::uint32_t x) {
                for (std::uint32_t i = 0; i < size_[x]; ++i) {
                    const Face& f = face_[fan(x)[i]];
                    if (std::find(f.begin(), f.end(), opposite_[0]) != f.end() &&
                        std::find(f.begin(), f.end(), opposite_[1]) != f.end())
                        return true;
                }
                return false;
            };
            if (has_both(u) && has_both(v)) return false;
        }
        return true;
    }

    // Moves u onto v; the new faces take the errors star_errors(u, v) gave them (`split`, in
    // the order of u's faces not on edge uv).
    void collapse(std::uint32_t u, std::uint32_t v, const FaceError* split) {
        std::size_t kept = 0;
        quadric_[v].add(quadric_[u]);
        weight_[v] += weight_[u];
        for (std::uint32_t i = 0; i < size_[u]; ++i) {
            const std::uint32_t fi = fan(u)[i];
            Face& f = face_[fi];
            if (std::find(f.begin(), f.end(), v) != f.end()) {
                face_alive_[fi] = 0; // the faces on the edge go: off the fans of their other vertices
                for (const std::uint32_t w : f) {
                    if (w == u) continue;
                    std::uint32_t* list = pool_.data() + begin_[w];
                    for (std::uint32_t j = 0; j < size_[w]; ++j)
                        if (list[j] == fi) {
                            std::copy(list + j + 1, list + size_[w], list + j);
                            --size_[w];
                            break;
                        }
                }
                continue;
            }
            for (std::uint32_t& w : f)
                if (w == u) w = v;
            face_error_[fi] = split[kept++];
            append(v, fi);
        }
        size_[u] = 0;
        alive_[u] = 0;
        neighbours(v, around_v_);
        if (movable_[v]) push(v, around_v_);
        for (const Neighbour& n : around_v_) // wake those that found no collapse before
            if (movable_[n.vertex] && alive_[n.vertex] && !queued_[n.vertex]) push(n.vertex);
    }

    void append(std::uint32_t v, std::uint32_t f) {
        if (size_[v] == capacity_[v]) { // move the fan to the end of the pool, twice as roomy
            const std::uint32_t at = std::uint32_t(pool_.size());
            pool_.resize(pool_.size() + 2 * capacity_[v]);
            std::copy(pool_.begin() + begin_[v], pool_.begin() + begin_[v] + size_[v], pool_.begin() + at);
            begin_[v] = at, capacity_[v] *= 2;
        }
        pool_[begin_[v] + size_[v]++] = f;
    }

    Shared& s_;
    std::vector<std::uint32_t> global_face_, global_; // local face and vertex -> global
    std::vector<Face> face_;                          // in local vertex numbers
    std::vector<char> face_alive_;
    std::vector<std::uint32_t> pool_, begin_, size_, capacity_; // the faces around each vertex
    std::vector<char> interior_, movable_, target_, alive_, queued_;
    std::vector<V3> position_, reference_;
    std::vector<FaceError> face_error_;
    std::vector<std::uint32_t> stamp_;
    std::vector<Quadric> quadric_;
    std::vector<double> weight_;
    std::vector<Entry> heap_; // a heap: std::push_heap, std::pop_heap
    static constexpr std::uint32_t empty_slot = std::numeric_limits<std::uint32_t>::max(); // no vertex has this number
    std::vector<std::pair<std::uint32_t, std::uint32_t>> table_; // (global vertex, local number)
    std::vector<Neighbour> around_, around_u_, around_v_;
    std::vector<std::uint32_t> opposite_, tag_, slot_, parent_, ring_;
    std::uint32_t tag_now_ = 0, ring_now_ = 0;
    std::vector<Candidate> candidates_;
    // star_errors': the fans as seen along n, the old faces' errors, per new face its largest
    // step and its error (one per face of u's not on edge uv, in fan order: collapse() follows it).
    // see_star's: u's star along n, the same for every collapse of u (seen once a try).
    bool star_seen_ = false, star_visible_ = false;
    V3 star_origin_{}, star_n_{}, star_t1_{}, star_t2_{};
    // An old face's split turned onto n: the lowest and highest offset along n, the farthest
    // across it; and its sector of directions from u.
    struct Turned {
        double below, above, across, start, end;
    };
    // A vertex of u's link: where it is seen, and how many new faces it is a corner of.
    struct Link {
        std::uint32_t vertex;
        Seen at;
        std::uint32_t new_faces;
    };
    // Per old and new face: its corners other than u (or v), as vertices and as links.
    std::vector<std::pair<Seen, Seen>> old_fan_, new_fan_;
    std::vector<std::array<std::uint32_t, 2>> old_ends_, old_link_, new_link_;
    std::vector<double> old_scale_, old_error_, step_, pair_below_, pair_above_, new_error_;
    std::vector<Turned> old_turned_;
    std::vector<Link> link_;
    std::vector<FaceError> new_split_, tried_split_;
    std::vector<char> holds_u_;
};

// Blocks of edge `edge` (the grid shifted by `shift` edges on every axis): the alive faces that
// are `active` by the block their centroid falls in, blocks in grid order, faces in their order.
void cut_into_blocks(const Shared& s, const std::vector<char>& active, const V3& lo, const V3& hi, double edge,
                     double shift, std::vector<std::uint32_t>& order, std::vector<std::size_t>& starts) {
    std::array<std::uint64_t, 3> dims{};
    for (int a = 0; a < 3; ++a) dims[a] = std::uint64_t((hi[a] - lo[a]) / edge + shift) + 1;
    const std::size_t n = s.faces.size();
    // The block of face f, worked out twice (to count, then to place) rather than kept: 4 bytes a
    // face at the simplifier's peak.
    const auto key = [&](std::size_t f) {
        std::uint64_t k = 0;
        for (int a = 2; a >= 0; --a) {
            const double c =
                (double(s.position[s.faces[f][0]][a]) + s.position[s.faces[f][1]][a] + s.position[s.faces[f][2]][a]) /
                3;
            k = k * dims[a] +
                std::min<std::uint64_t>(dims[a] - 1, std::uint64_t(std::max(0.0, (c - lo[a]) / edge + shift)));
        }
        return k;
    };
    const std::uint64_t blocks = dims[0] * dims[1] * dims[2];
    std::vector<std::size_t> count(blocks + 1, 0);
    for (std::size_t f = 0; f < n; ++f)
        if (s.face_alive[f] && active[f]) ++count[key(f) + 1];
    for (std::size_t b = 0; b < blocks; ++b) count[b + 1] += count[b];
    order.resize(count[blocks]);
    starts.clear();
    for (std::size_t b = 0; b < blocks; ++b)
        if (count[b + 1] > count[b]) starts.push_back(count[b]);
    starts.push_back(order.size());
    for (std::size_t f = 0; f < n; ++f)
        if (s.face_alive[f] && active[f]) order[count[key(f)]++] = std::uint32_t(f);
}

} // namespace

SimplifyReport simplify_mesh(Mesh& mesh, const SimplifyOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    SimplifyReport report;
    report.triangles_before = report.triangles_after = mesh.triangles.size();
    report.error = options.error;
    if (!(options.error > 0) || mesh.triangles.empty()) return report;

    const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
    Shared s{mesh.positions, mesh.triangles, {}, {}, {}, {}, {}, {}, options.error};
    V3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
    V3 hi{-lo[0], -lo[1], -lo[2]};
    for (const auto& p : mesh.positions)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], double(p[a])), hi[a] = std::max(hi[a], double(p[a]));
    // The mean edge length, from at most 65536 faces spread over the mesh.
    double edge_sum = 0;
    std::size_t edges = 0;
    for (std::size_t f = 0; f < nf; f += nf / 65536 + 1, edges += 3)
        for (int k = 0; k < 3; ++k) {
            const auto &a = mesh.positions[mesh.triangles[f][k]], &b = mesh.positions[mesh.triangles[f][(k + 1) % 3]];
            edge_sum += norm({double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]});
        }
    s.slot.assign(nv, 0);
    s.locked.assign(nv, 0);
    s.face_alive.assign(nf, 1);
    s.face_error.assign(nf, FaceError{});
    if (options.lock_border) { // a vertex on an edge only one face uses
        std::vector<std::uint64_t> all;
        all.reserve(3 * nf);
        for (const Face& f : mesh.triangles)
            for (int k = 0; k < 3; ++k) {
                const std::uint64_t a = f[k], b = f[(k + 1) % 3];
                all.push_back(std::min(a, b) << 32 | std::max(a, b));
            }
        std::sort(all.begin(), all.end());
        for (std::size_t i = 0; i < all.size();) {
            std::size_t j = i;
            while (j < all.size() && all[j] == all[i]) ++j;
            if (j - i == 1) s.locked[all[i] >> 32] = s.locked[all[i] & 0xffffffffu] = 1;
            i = j;
        }
    }

    // Blocks of about 32 mean edges: a thousand or some thousands of faces each, ~10% held.
    const double block_edge = 32 * edge_sum / double(std::max<std::size_t>(1, edges));
    std::vector<std::uint32_t> order;
    std::vector<std::size_t> starts;
    tbb::enumerable_thread_specific<Block> workspace([&] { return Block(s); });
    // Later passes take only the faces near the vertices the pass before held (around them, and
    // around their neighbours): elsewhere the blocks have done what they could.
    std::vector<char> active(nf, 1), held(nv, 0);
    constexpr std::uint32_t nobody = std::numeric_limits<std::uint32_t>::max();
    constexpr int passes = 3;
    for (int pass = 0; pass < passes && block_edge > 0; ++pass) {
        cut_into_blocks(s, active, lo, hi, block_edge, pass % 2 ? 0.5 : 0.0, order, starts);
        const std::size_t blocks = starts.size() - 1;
        std::vector<std::uint32_t> owner(nv,
                                         nobody); // the first block to use each vertex (released before the blocks run)
        std::fill(held.begin(), held.end(), 0);
        for (std::size_t b = 0; b < blocks; ++b)
            for (std::size_t i = starts[b]; i < starts[b + 1]; ++i)
                for (const std::uint32_t v : s.faces[order[i]]) {
                    if (owner[v] == nobody)
                        owner[v] = std::uint32_t(b);
                    else if (owner[v] != b)
                        held[v] = 1;
                }
        s.outside = held;
        if (pass > 0) // faces left out of this pass hold their vertices too
            for (std::size_t f = 0; f < nf; ++f)
                if (s.face_alive[f] && !active[f])
                    for (const std::uint32_t v : s.faces[f]) s.outside[v] = 1;
        // The first pass's slots: the vertices blocks share first, then per block a range as long
        // as the vertices only it has.
        std::vector<std::uint32_t> first_slot(blocks + 1, 0);
        if (pass == 0) {
            std::uint32_t shared = 0;
            for (std::uint32_t v = 0; v < nv; ++v)
                if (held[v])
                    s.slot[v] = shared++;
                else if (owner[v] != nobody)
                    ++first_slot[owner[v] + 1];
            first_slot[0] = shared;
            for (std::size_t b = 0; b < blocks; ++b) first_slot[b + 1] += first_slot[b];
            s.stored.reset(new PlaneSums[first_slot[blocks]]);
            std::fill(s.stored.get(), s.stored.get() + shared, PlaneSums{});
            // The planes of the original faces around the vertices blocks share, in face order.
            for (std::size_t f = 0; f < nf; ++f) {
                const Face& t = s.faces[f];
                if (!held[t[0]] && !held[t[1]] && !held[t[2]]) continue;
                const Plane plane = face_plane(s.position, t);
                for (const std::uint32_t v : t)
                    if (held[v]) plane.add_to(s.stored[s.slot[v]]);
            }
            for (std::uint32_t i = 0; i < shared; ++i) unit_normal(s.stored[i].reference);
        }
        std::vector<std::uint32_t>().swap(owner);
        tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
            Block& mine = workspace.local();
            mine.load(order.data() + starts[b], starts[b + 1] - starts[b]);
            mine.run(pass == 0, first_slot[b]);
        });
        if (pass + 1 == passes) break;
        const auto touches = [&](std::size_t f) {
            return s.face_alive[f] && (held[s.faces[f][0]] || held[s.faces[f][1]] || held[s.faces[f][2]]);
        };
        for (int ring = 0; ring < 2; ++ring) { // held vertices, then their neighbours too
            std::vector<char> near = held;
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf, 1 << 14),
                              [&](const tbb::blocked_range<std::size_t>& range) {
                                  for (std::size_t f = range.begin(); f < range.end(); ++f)
                                      if (touches(f))
                                          for (const std::uint32_t v : s.faces[f])
                                              std::atomic_ref<char>(near[v]).store(1, std::memory_order_relaxed);
                              });
            held.swap(near);
        }
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf, 1 << 14),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              for (std::size_t f = range.begin(); f < range.end(); ++f) active[f] = touches(f);
                          });
    }

    std::size_t kept = 0;
    double reached = 0;
    for (std::size_t f = 0; f < nf; ++f)
        if (s.face_alive[f])
            mesh.triangles[kept++] = mesh.triangles[f], reached = std::max(reached, bound(s.face_error[f]));
    mesh.triangles.resize(kept);
    // What the passes held goes before the clean-up takes its own.
    s.stored.reset();
    workspace.clear();
    for (std::vector<std::uint32_t>* v : {&s.slot, &order}) std::vector<std::uint32_t>().swap(*v);
    remove_unused_vertices(mesh);
    // A kept normal can end up facing away from the larger faces now around its vertex: there it
    // becomes theirs, as viewers shade by it.
    if (!mesh.normals.empty()) agree_normals_with_faces(mesh);

    report.triangles_after = mesh.triangles.size();
    report.result_error = reached;
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace lasmesh
