// SPDX-License-Identifier: Apache-2.0
#include "mesh/tile_facing.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>
#include <tuple>
#include <utility>

namespace lasmesh {

namespace {

// Two triangles closer to one plane than this (the cosine of 60 degrees) continue one surface
// across the edge they share; not two sheets meeting at an angle (a wall on a deck), nor a
// plate's face folding back into its other face.
constexpr double continues_cosine = 0.5;

// Two pieces that their tiles faced apart join only where their shared edges' say is at least
// this share of the smaller one's border (its edges used by one of its tile's triangles, shared
// or not): a stray edge at a plate's rim does not turn a plate's face that a tile border cut from
// it, while a deck faced down across a tile, bordered by its neighbours all round, turns.
constexpr double join_share = 0.1;

std::array<double, 3> cross_of(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const auto& a = m.positions[t[0]];
    const auto& b = m.positions[t[1]];
    const auto& c = m.positions[t[2]];
    const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]},
                 v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}

// Union-find whose nodes remember whether they run against their parent.
struct TurnSets {
    std::vector<std::uint32_t> parent;
    std::vector<char> against_parent;

    explicit TurnSets(std::size_t n) : parent(n), against_parent(n, 0) {
        for (std::uint32_t i = 0; i < n; ++i) parent[i] = i;
    }
    // The root of `v`, and whether v runs against it.
    std::pair<std::uint32_t, bool> find(std::uint32_t v) {
        bool against = false;
        std::uint32_t r = v;
        while (parent[r] != r) against ^= against_parent[r] != 0, r = parent[r];
        bool left = against; // every node on the way straight onto the root, with its turn against it
        for (std::uint32_t u = v; parent[u] != u;) {
            const std::uint32_t next = parent[u];
            const bool next_left = left ^ (against_parent[u] != 0);
            parent[u] = r, against_parent[u] = left;
            u = next, left = next_left;
        }
        return {r, against};
    }
    void join(std::uint32_t a, std::uint32_t b, bool against) {
        const auto [ra, ta] = find(a);
        const auto [rb, tb] = find(b);
        if (ra == rb) return;
        const auto [root, child] = std::minmax(ra, rb);
        parent[child] = root, against_parent[child] = ta ^ tb ^ against;
    }
};

// The net say of the edges two regions share: those running alike less those running against.
using SharedEdges = std::map<std::pair<std::uint32_t, std::uint32_t>, long long>; // (a < b) -> say

SharedEdges shared_edges(const std::vector<TileRegions>& tiles, const std::vector<std::uint32_t>& first_region) {
    struct Edge {
        std::array<float, 3> low, high; // its ends, ordered
        std::uint32_t region, tile;
        const TileRegions::BorderEdge* edge;
    };
    std::vector<Edge> edges;
    for (std::uint32_t k = 0; k < tiles.size(); ++k)
        for (const TileRegions::BorderEdge& e : tiles[k].border) {
            const auto [low, high] = std::minmax(e.from, e.to);
            edges.push_back({low, high, first_region[k] + e.region, k, &e});
        }
    std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
        return std::tie(a.low, a.high, a.region, a.edge->from) < std::tie(b.low, b.high, b.region, b.edge->from);
    });
    SharedEdges say;
    for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
        const Edge &a = edges[i], &b = edges[i + 1];
        if (a.low != b.low || a.high != b.high || a.tile == b.tile) continue; // within a tile: its sheet's own
        const bool against = a.edge->from == b.edge->from; // the same direction: the triangles face apart
        const auto& n = a.edge->normal;
        const auto& m = b.edge->normal;
        const double facing = double(n[0]) * m[0] + double(n[1]) * m[1] + double(n[2]) * m[2];
        if (against ? facing > -continues_cosine : facing < continues_cosine) continue;
        say[std::minmax(a.region, b.region)] += against ? -1 : 1;
    }
    return say;
}

// Joins the regions the pair with the largest net say first, summing a joined piece's say with
// each other piece.
void join_by_say(const SharedEdges& say, const std::vector<double>& area, std::vector<double> border, TurnSets& sets) {
    std::vector<std::map<std::uint32_t, long long>> around(sets.parent.size()); // per joined piece's node
    std::vector<double> own = area; // per joined piece's node: its area as its tiles faced it, less the rest
    for (const auto& [pair, s] : say)
        if (s != 0) around[pair.first][pair.second] = s, around[pair.second][pair.first] = s;
    using Entry = std::tuple<long long, std::int64_t, std::int64_t>; // |say|, then the lower pair first
    std::priority_queue<Entry> queue;
    const auto push = [&](long long s, std::uint32_t a, std::uint32_t b) {
        queue.emplace(std::llabs(s), -std::int64_t{std::min(a, b)}, -std::int64_t{std::max(a, b)});
    };
    for (const auto& [pair, s] : say)
        if (s != 0) push(s, pair.first, pair.second);
    std::vector<char> gone(around.size(), 0);
    while (!queue.empty()) {
        const auto [size, low, high] = queue.top();
        queue.pop();
        const auto a = static_cast<std::uint32_t>(-low), b = static_cast<std::uint32_t>(-high);
        if (gone[a] || gone[b]) continue;
        const auto at = around[a].find(b);
        if (at == around[a].end() || std::llabs(at->second) != size) continue; // an older sum
        const bool against = at->second < 0;
        const double joined = own[a] + (against ? -own[b] : own[b]);
        const bool apart = std::abs(joined) < std::abs(own[a]) + std::abs(own[b]); // their tiles faced them apart
        if (apart && double(size) < join_share * std::min(border[a], border[b])) continue;
        own[a] = joined, own[b] = against ? -joined : joined;
        border[a] = border[b] = border[a] + border[b];
        sets.join(a, b, against);
        // The piece with more neighbours takes the other's: its say with each, turned if the two run against.
        const std::uint32_t keep = around[a].size() >= around[b].size() ? a : b, other = keep == a ? b : a;
        around[keep].erase(other);
        for (const auto& [c, s] : around[other]) {
            if (c == keep) continue;
            around[c].erase(other);
            long long& sum = around[keep][c];
            sum += against ? -s : s;
            if (sum == 0) {
                around[keep].erase(c), around[c].erase(keep);
                continue;
            }
            around[c][keep] = sum;
            push(sum, keep, c);
        }
        std::map<std::uint32_t, long long>().swap(around[other]);
        gone[other] = 1;
    }
}

} // namespace

TileRegions tile_regions(const Mesh& sheet) {
    const std::size_t n = sheet.triangles.size();
    // Every directed edge with its triangle, sorted: an edge's uses each way side by side.
    std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> directed;
    directed.reserve(3 * n);
    for (std::uint32_t i = 0; i < n; ++i)
        for (int e = 0; e < 3; ++e) directed.emplace_back(sheet.triangles[i][e], sheet.triangles[i][(e + 1) % 3], i);
    std::sort(directed.begin(), directed.end());
    const auto uses = [&](std::uint32_t from, std::uint32_t to) {
        const auto range = std::equal_range(
            directed.begin(), directed.end(), std::tuple(from, to, 0u), [](const auto& x, const auto& y) {
                return std::pair(std::get<0>(x), std::get<1>(x)) < std::pair(std::get<0>(y), std::get<1>(y));
            });
        return std::pair(range.first, static_cast<std::size_t>(range.second - range.first));
    };
    std::vector<std::uint32_t> root(n);
    for (std::uint32_t i = 0; i < n; ++i) root[i] = i;
    const auto find = [&](std::uint32_t i) {
        while (root[i] != i) i = root[i] = root[root[i]];
        return i;
    };
    TileRegions regions;
    std::vector<std::pair<std::uint32_t, int>> border; // triangle, edge
    for (std::uint32_t i = 0; i < n; ++i)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t from = sheet.triangles[i][e], to = sheet.triangles[i][(e + 1) % 3];
            const auto [forward, ahead] = uses(from, to);
            const auto [backward, behind] = uses(to, from);
            if (ahead + behind == 1) border.emplace_back(i, e);
            if (ahead == 1 && behind == 1) { // two triangles running opposite ways: facing alike
                const std::uint32_t a = find(i), b = find(std::get<2>(*backward));
                if (a != b) root[std::max(a, b)] = std::min(a, b);
            }
        }
    regions.of_triangle.resize(n);
    const double cell_area = sheet.cell_size > 0 ? sheet.cell_size * sheet.cell_size : 1;
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t r = find(i);
        if (r == i)
            regions.of_triangle[i] = static_cast<std::uint32_t>(regions.area.size()), regions.area.push_back(0);
        else
            regions.of_triangle[i] = regions.of_triangle[r];
        const std::array<double, 3> c = cross_of(sheet, sheet.triangles[i]);
        regions.area[regions.of_triangle[i]] += 0.5 * std::hypot(c[0], c[1], c[2]) / cell_area;
    }
    for (const auto& [i, e] : border) {
        const auto& t = sheet.triangles[i];
        std::array<double, 3> c = cross_of(sheet, t);
        const double length = std::hypot(c[0], c[1], c[2]);
        if (length > 0)
            for (double& v : c) v /= length;
        regions.border.push_back({sheet.positions[t[e]],
                                  sheet.positions[t[(e + 1) % 3]],
                                  {float(c[0]), float(c[1]), float(c[2])},
                                  regions.of_triangle[i]});
    }
    return regions;
}

std::vector<std::vector<char>> facing_turns(const std::vector<TileRegions>& tiles) {
    std::vector<std::uint32_t> first_region; // per tile, its regions' numbers over all tiles
    std::uint32_t count = 0;
    for (const TileRegions& t : tiles)
        first_region.push_back(count), count += static_cast<std::uint32_t>(t.area.size());
    const SharedEdges say = shared_edges(tiles, first_region);
    std::vector<double> area(count), kept(count, 0); // kept: per root, its pieces' area signed by their turn
    for (std::uint32_t k = 0; k < tiles.size(); ++k)
        for (std::size_t r = 0; r < tiles[k].area.size(); ++r) area[first_region[k] + r] = tiles[k].area[r];
    std::vector<double> border(count, 0);
    for (std::uint32_t k = 0; k < tiles.size(); ++k)
        for (const TileRegions::BorderEdge& e : tiles[k].border) border[first_region[k] + e.region] += 1;
    TurnSets sets(count);
    join_by_say(say, area, border, sets);
    // Each joined piece faces the way most of its area faced in its tiles.
    std::vector<std::pair<std::uint32_t, bool>> root(count);
    for (std::uint32_t r = 0; r < count; ++r) {
        root[r] = sets.find(r);
        kept[root[r].first] += root[r].second ? -area[r] : area[r];
    }
    std::vector<char> turn(count);
    for (std::uint32_t r = 0; r < count; ++r) turn[r] = (kept[root[r].first] < 0) != root[r].second;
    // Then each region on its own, where turning it leaves more shared edges alike (by
    // join_share of its border more, when that turns it from its tile's facing): each turn raises
    // the count of edges alike less join_share of the borders of the regions turned, so the
    // passes end.
    std::vector<std::vector<std::pair<std::uint32_t, long long>>> around(count);
    for (const auto& [pair, s] : say)
        around[pair.first].emplace_back(pair.second, s), around[pair.second].emplace_back(pair.first, s);
    for (bool changed = true; changed;) {
        changed = false;
        for (std::uint32_t r = 0; r < count; ++r) {
            long long alike = 0; // more shared edges running alike, were r turned
            for (const auto& [other, s] : around[r]) alike += turn[r] == turn[other] ? -s : s;
            const double gain = double(alike) + (turn[r] ? join_share : -join_share) * border[r];
            if (gain > 0) turn[r] = !turn[r], changed = true;
        }
    }
    std::vector<std::vector<char>> turns(tiles.size());
    for (std::uint32_t k = 0; k < tiles.size(); ++k)
        turns[k].assign(turn.begin() + first_region[k], turn.begin() + first_region[k] + tiles[k].area.size());
    return turns;
}

void turn_regions(Mesh& sheet, const TileRegions& regions, const std::vector<char>& turn) {
    std::vector<char> normal_turned(sheet.positions.size(), 0), normal_set(sheet.positions.size(), 0);
    for (std::size_t i = 0; i < sheet.triangles.size(); ++i) {
        const bool turned = turn[regions.of_triangle[i]] != 0;
        auto& t = sheet.triangles[i];
        for (const std::uint32_t v : t)
            if (!normal_set[v]) normal_set[v] = 1, normal_turned[v] = turned;
        if (turned) std::swap(t[1], t[2]);
    }
    if (sheet.normals.empty()) return;
    for (std::size_t v = 0; v < sheet.positions.size(); ++v)
        if (normal_turned[v])
            for (float& c : sheet.normals[v]) c = -c;
}

} // namespace lasmesh
