// SPDX-License-Identifier: Apache-2.0
// tile_sheets_bench: whether the sheet can be meshed tile by tile (tools/bench_tile_sheets.sh).
// Accumulates a LAS file as lasmesh does by default, extracts the whole grid's sheet, then each
// tile's (TILE x TILE cells in x and y, all of z) from the tile's bricks and a halo of HALO
// cells round it, with the whole grid's noise and outside (sheet_survey), or with --own each
// tile's own; keeps each tile's triangles whose centroid lies in it and joins them (vertices at
// the same place, to 0.1 mm, made one). Reports both meshes' triangles, their border edges (all,
// and those within a cell of a tile's border: the cracks a tiling would add), edges whose two
// triangles face apart, and the triangles only one of the two meshes has. Writes PREFIX-whole.ply
// and PREFIX-tiled.ply (small pieces removed from each, not simplified) for
// `lasgen --scene deck --measure`. With --join, the tiles' pieces are first turned to face as one
// (face_tiles_as_one).
//
// Usage: tile_sheets_bench INPUT.las TILE HALO PREFIX [--own] [--join]
#include "build_steps.hpp"
#include "io/ply_writer.hpp"
#include "lasmesh/build_mesh.hpp"
#include "lasmesh/mesh_pieces.hpp"
#include "mesh/marching_cubes.hpp"
#include "mesh/outside_space.hpp"
#include "mesh/surface_sheet.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <map>
#include <string>
#include <tuple>
#include <unordered_map>

using namespace lasmesh;

namespace {

// The tiles' sheets made to face as one (--join): each tile's regions (triangles joined across
// edges two of them share running opposite ways) are pieces; two tiles' pieces that share edges
// (the same two positions, the two triangles nearly in one plane) run alike or against each
// other as most of those edges say; the pairs with the most edges are joined first, and each
// joined piece keeps the way most of its area faced in its tiles (each tile's sheet faced its
// pieces as the whole grid's sheet does: by the spanning tree and the outside).
struct TilesFaced {
    std::size_t shared_edges = 0; // edges two tiles' sheets share
    std::size_t against = 0;      // of those, where the two ran against each other before
    std::size_t disagreeing = 0;  // shared edges overruled: by more of their two pieces' edges, or by heavier links
    std::size_t turned = 0;       // the tiles' pieces turned over
};

using Place = std::array<float, 3>;

// Two triangles closer to one plane than this (the cosine of 60 degrees) continue one surface.
constexpr double continues_cosine = 0.5;

// An edge of one triangle in a tile: its ends in the triangle's winding, and its piece.
struct BorderEdge {
    Place from, to;
    std::uint32_t node; // the tile's piece, numbered over all tiles
    std::uint32_t tile;
    std::array<double, 3> normal; // the triangle's, unit, the way it faces
};

// The cross product of triangle t's edges from its first corner: along its normal, the way its
// winding faces, twice its area long.
std::array<double, 3> cross_of(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const auto& a = m.positions[t[0]];
    const auto& b = m.positions[t[1]];
    const auto& c = m.positions[t[2]];
    const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]},
                 v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}

double twice_area(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const std::array<double, 3> n = cross_of(m, t);
    return std::hypot(n[0], n[1], n[2]);
}

std::array<double, 3> unit_normal(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    std::array<double, 3> n = cross_of(m, t);
    const double length = std::hypot(n[0], n[1], n[2]);
    if (length > 0)
        for (double& c : n) c /= length;
    return n;
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
        // Every node on the way straight onto the root, with its turn against it.
        bool left = against;
        for (std::uint32_t u = v; parent[u] != u;) {
            const std::uint32_t next = parent[u];
            const bool next_left = left ^ (against_parent[u] != 0);
            parent[u] = r, against_parent[u] = left;
            u = next, left = next_left;
        }
        return {r, against};
    }
    // Joins a and b, running against each other when `against`; false when they were already
    // joined the other way.
    bool join(std::uint32_t a, std::uint32_t b, bool against) {
        const auto [ra, ta] = find(a);
        const auto [rb, tb] = find(b);
        if (ra == rb) return (ta ^ tb) == against;
        const auto [root, child] = std::minmax(ra, rb); // the smaller number roots: the same for any order
        parent[child] = root, against_parent[child] = ta ^ tb ^ against;
        return true;
    }
};

// Each triangle's region: the triangles joined across edges that two triangles share running
// opposite ways (facing alike), numbered by their first triangle. A region faces one way
// throughout; a tile's connected part may hold several (joined at a vertex, or across an edge
// that three triangles share), and the tiles' pieces are joined region by region.
std::vector<std::uint32_t> oriented_regions(const Mesh& m) {
    std::vector<std::uint32_t> root(m.triangles.size());
    for (std::uint32_t i = 0; i < root.size(); ++i) root[i] = i;
    const auto find = [&](std::uint32_t i) {
        while (root[i] != i) i = root[i] = root[root[i]];
        return i;
    };
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> users; // (from, to) -> triangles
    for (std::uint32_t i = 0; i < m.triangles.size(); ++i)
        for (int e = 0; e < 3; ++e) users[{m.triangles[i][e], m.triangles[i][(e + 1) % 3]}].push_back(i);
    for (const auto& [edge, ones] : users) {
        if (ones.size() != 1 || edge.first > edge.second) continue;
        const auto back = users.find({edge.second, edge.first});
        if (back == users.end() || back->second.size() != 1) continue;
        const std::uint32_t a = find(ones[0]), b = find(back->second[0]);
        if (a != b) root[std::max(a, b)] = std::min(a, b);
    }
    for (std::uint32_t i = 0; i < root.size(); ++i) root[i] = root[root[i]];
    return root;
}

TilesFaced face_tiles_as_one(std::vector<Mesh>& tiles) {
    TilesFaced report;
    // The tiles' regions, numbered tile by tile, with their areas (twice); each tile's border
    // edges (used by one triangle).
    std::vector<std::vector<std::uint32_t>> node(tiles.size()); // per tile, per triangle
    std::vector<double> vote;
    std::vector<BorderEdge> border;
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        const Mesh& m = tiles[k];
        const std::vector<std::uint32_t> region = oriented_regions(m);
        node[k].resize(m.triangles.size());
        for (std::uint32_t i = 0; i < region.size(); ++i) {
            if (region[i] == i) node[k][i] = static_cast<std::uint32_t>(vote.size()), vote.push_back(0);
            node[k][i] = node[k][region[i]];
            vote[node[k][i]] += twice_area(m, m.triangles[i]);
        }
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
        for (const auto& t : m.triangles)
            for (int e = 0; e < 3; ++e) ++uses[std::minmax(t[e], t[(e + 1) % 3])];
        for (std::uint32_t i = 0; i < m.triangles.size(); ++i) {
            const auto& t = m.triangles[i];
            for (int e = 0; e < 3; ++e)
                if (uses[std::minmax(t[e], t[(e + 1) % 3])] == 1)
                    border.push_back({m.positions[t[e]], m.positions[t[(e + 1) % 3]], node[k][i],
                                      static_cast<std::uint32_t>(k), unit_normal(m, t)});
        }
    }
    // Edges with the same two ends, whichever way round, side by side; each pair of tiles' pieces
    // that share one linked (the order of the list fixed by the places and pieces alone).
    const auto ends = [](const BorderEdge& e) { return std::minmax(e.from, e.to); };
    std::sort(border.begin(), border.end(), [&](const BorderEdge& a, const BorderEdge& b) {
        return std::tuple(ends(a), a.node, a.from) < std::tuple(ends(b), b.node, b.from);
    });
    // The edges two tiles' regions share, counted per pair of regions and per way they run.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::array<std::size_t, 2>> shared; // [alike, against]
    for (std::size_t i = 0; i + 1 < border.size(); ++i) {
        const BorderEdge &a = border[i], &b = border[i + 1];
        if (ends(a) != ends(b) || a.tile == b.tile) continue; // within a tile, its own sheet's business
        const bool against = a.from == b.from;                // the same direction: the two triangles face apart
        // One surface continues across the edge only where the two triangles lie nearly in one
        // plane, facing the way their winding says: not where two sheets meet at an angle (a
        // wall on a deck), nor where a plate's face folds back into its other face.
        const double facing = a.normal[0] * b.normal[0] + a.normal[1] * b.normal[1] + a.normal[2] * b.normal[2];
        if (against ? facing > -continues_cosine : facing < continues_cosine) continue;
        ++report.shared_edges;
        report.against += against;
        ++shared[std::minmax(a.node, b.node)][against];
    }
    // Each pair of regions runs the way most of their shared edges say; the pairs with the most
    // edges joined first (a maximum spanning forest, as Hoppe et al. orient planes): the two
    // tiles' meshes differ a little near their border (each window's planes turned its own way),
    // and an odd link there must not decide for the long stretch beside it.
    struct Link {
        std::size_t weight;
        std::uint32_t a, b;
        bool against;
        std::size_t minority;
    };
    std::vector<Link> links;
    for (const auto& [pair, counts] : shared) {
        const bool against = counts[1] > counts[0];
        links.push_back({counts[against], pair.first, pair.second, against, counts[!against]});
    }
    std::sort(links.begin(), links.end(), [](const Link& x, const Link& y) {
        return std::tuple(y.weight, x.a, x.b) < std::tuple(x.weight, y.a, y.b);
    });
    TurnSets sets(vote.size());
    for (const Link& link : links) {
        report.disagreeing += link.minority;
        if (!sets.join(link.a, link.b, link.against)) report.disagreeing += link.weight;
    }
    // Each joined piece's area as its tiles faced it, its pieces' signed by their turn against the root.
    std::vector<double> total(vote.size(), 0);
    std::vector<std::pair<std::uint32_t, bool>> root(vote.size());
    for (std::uint32_t n = 0; n < vote.size(); ++n) {
        root[n] = sets.find(n);
        total[root[n].first] += root[n].second ? -vote[n] : vote[n];
    }
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        Mesh& m = tiles[k];
        // A vertex's normal turns with the first of its triangles (the regions at a vertex may turn apart).
        std::vector<char> normal_turned(m.positions.size(), 0), normal_set(m.positions.size(), 0);
        std::uint32_t last = ~std::uint32_t{0};
        for (std::uint32_t i = 0; i < m.triangles.size(); ++i) {
            const auto [r, against] = root[node[k][i]];
            const bool turn = (total[r] < 0) != against;
            auto& t = m.triangles[i];
            for (const std::uint32_t v : t)
                if (!normal_set[v]) normal_set[v] = 1, normal_turned[v] = turn;
            if (turn) std::swap(t[1], t[2]);
            if (turn && node[k][i] != last) ++report.turned;
            last = node[k][i];
        }
        for (std::uint32_t v = 0; v < m.positions.size() && !m.normals.empty(); ++v)
            if (normal_turned[v])
                for (float& c : m.normals[v]) c = -c;
    }
    return report;
}

// A position to 0.1 mm, as one key.
std::uint64_t place_key(const std::array<float, 3>& p) {
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) key = key << 21 | (std::uint64_t(std::llround(double(p[a]) * 1e4)) & 0x1fffff);
    return key;
}

// `from`'s triangles (all, or those keep() takes) appended to `to`, vertices at one place made one.
template <class Keep>
void append_welded(Mesh& to, std::unordered_map<std::uint64_t, std::uint32_t>& at, const Mesh& from, Keep keep) {
    for (const auto& t : from.triangles) {
        if (!keep(t)) continue;
        std::array<std::uint32_t, 3> joined{};
        for (int k = 0; k < 3; ++k) {
            const auto& p = from.positions[t[k]];
            const auto [it, fresh] = at.try_emplace(place_key(p), std::uint32_t(to.positions.size()));
            if (fresh) {
                to.positions.push_back(p);
                if (!from.colors.empty()) to.colors.push_back(from.colors[t[k]]);
            }
            joined[k] = it->second;
        }
        to.triangles.push_back(joined);
    }
}

struct EdgeCounts {
    std::size_t border = 0, border_at_tiles = 0, facing_apart = 0;
};

EdgeCounts edge_counts(const Mesh& m, double cell, std::int64_t tile) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    const auto at_tiles = [&](std::uint32_t v) {
        for (int a = 0; a < 2; ++a) {
            const double c = double(m.positions[v][a]) / cell;
            if (std::abs(c - double(tile) * std::round(c / double(tile))) < 1) return true;
        }
        return false;
    };
    EdgeCounts counts;
    for (const auto& [edge, uses] : directed) {
        const auto back = directed.find({edge.second, edge.first});
        const int back_uses = back == directed.end() ? 0 : back->second;
        if (uses + back_uses == 1) {
            ++counts.border;
            counts.border_at_tiles += at_tiles(edge.first) && at_tiles(edge.second);
        }
        counts.facing_apart += uses >= 2 && back_uses == 0;
    }
    return counts;
}

// Each triangle as its corners' keys from the lowest on (its winding kept), sorted.
std::vector<std::array<std::uint64_t, 3>> triangle_keys(const Mesh& m) {
    std::vector<std::array<std::uint64_t, 3>> keys;
    for (const auto& t : m.triangles) {
        std::array<std::uint64_t, 3> k{place_key(m.positions[t[0]]), place_key(m.positions[t[1]]),
                                       place_key(m.positions[t[2]])};
        std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
        keys.push_back(k);
    }
    std::sort(keys.begin(), keys.end());
    return keys;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 5) {
        std::fprintf(stderr, "usage: tile_sheets_bench INPUT.las TILE HALO PREFIX [--own]\n");
        return 2;
    }
    const std::string input = argv[1], prefix = argv[4];
    const std::int64_t tile = std::atoll(argv[2]), halo = std::atoll(argv[3]);
    bool own = false, joined = false;
    for (int i = 5; i < argc; ++i)
        own = own || std::string(argv[i]) == "--own", joined = joined || std::string(argv[i]) == "--join";
    const AccumulatedInputs accumulated = accumulate_inputs({input}, BuildOptions{});
    const CellGrid& grid = accumulated.accumulation->grid;
    const double iso = automatic_iso(grid), cell = grid.spec.cell_size;
    std::printf("grid %u x %u x %u cells of %.4f, iso %.1f; tiles of %lld cells, halo %lld%s\n", grid.spec.dims[0],
                grid.spec.dims[1], grid.spec.dims[2], cell, iso, static_cast<long long>(tile),
                static_cast<long long>(halo), own ? ", each tile its own noise and outside" : "");
    std::unordered_map<std::uint64_t, std::uint32_t> whole_at, tiled_at;
    Mesh whole, tiled;
    append_welded(whole, whole_at, extract_sheet(grid, iso), [](const auto&) { return true; });
    const SheetSurvey survey = sheet_survey(grid, iso);
    std::vector<Mesh> tiles;
    for (std::int64_t y = 0; y < std::int64_t{grid.spec.dims[1]}; y += tile)
        for (std::int64_t x = 0; x < std::int64_t{grid.spec.dims[0]}; x += tile) {
            const CellGrid part = bricks_within(grid, x - halo, x + tile + halo, y - halo, y + tile + halo);
            if (part.cells.empty()) continue;
            Mesh sheet = own ? extract_sheet(part, iso) : extract_sheet(part, iso, survey);
            std::erase_if(sheet.triangles, [&](const std::array<std::uint32_t, 3>& t) {
                double c[2]{};
                for (int k = 0; k < 3; ++k)
                    for (int a = 0; a < 2; ++a) c[a] += double(sheet.positions[t[k]][a]) / (3 * cell);
                return c[0] < double(x) || c[0] >= double(x + tile) || c[1] < double(y) || c[1] >= double(y + tile);
            });
            tiles.push_back(std::move(sheet));
        }
    if (joined) {
        const TilesFaced faced = face_tiles_as_one(tiles);
        std::printf("joined: %zu edges shared by two tiles, %zu of them running against each other; %zu tiles' "
                    "pieces turned; %zu shared edges overruled\n",
                    faced.shared_edges, faced.against, faced.turned, faced.disagreeing);
    }
    for (const Mesh& sheet : tiles) append_welded(tiled, tiled_at, sheet, [](const auto&) { return true; });
    const auto a = triangle_keys(whole), b = triangle_keys(tiled);
    std::vector<std::array<std::uint64_t, 3>> only_whole, only_tiled;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(only_whole));
    std::set_difference(b.begin(), b.end(), a.begin(), a.end(), std::back_inserter(only_tiled));
    for (const auto& [name, m] : {std::pair<const char*, const Mesh*>{"whole", &whole}, {"tiled", &tiled}}) {
        const EdgeCounts e = edge_counts(*m, cell, tile);
        std::printf("%s: %zu triangles; border edges %zu, within a cell of a tile's border %zu; edges whose "
                    "triangles face apart %zu\n",
                    name, m->triangles.size(), e.border, e.border_at_tiles, e.facing_apart);
    }
    std::size_t turned = 0; // of those only in the whole grid's, the tiles' have with the other winding
    for (std::array<std::uint64_t, 3> k : only_whole) {
        std::swap(k[1], k[2]);
        turned += std::binary_search(only_tiled.begin(), only_tiled.end(), k);
    }
    std::printf("%zu tiles; triangles only in the whole grid's sheet %zu (of them facing the other way in the "
                "tiles' %zu), only in the tiles' %zu\n",
                tiles.size(), only_whole.size(), turned, only_tiled.size());
    for (Mesh* m : {&whole, &tiled}) {
        m->origin = grid.spec.origin, m->cell_size = cell;
        remove_small_pieces(*m, MinPiece{});
    }
    write_ply(whole, prefix + "-whole.ply");
    write_ply(tiled, prefix + "-tiled.ply");
}
