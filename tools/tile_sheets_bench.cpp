// SPDX-License-Identifier: Apache-2.0
// tile_sheets_bench: whether the sheet can be meshed tile by tile (tools/bench_tile_sheets.sh).
// Accumulates a LAS file as lasmesh does by default, extracts the whole grid's sheet, then the
// tiles' (TILE x TILE cells in x and y, all of z, each from its bricks and a halo of HALO cells
// round it: sheets_of_tiles), and joins each mesh's vertices at the same place (to 0.1 mm).
// Reports both meshes' triangles, their border edges (all, and those within a cell of a tile's
// border: the cracks a tiling would add), edges whose two triangles face apart, and the triangles
// only one of the two meshes has. Writes PREFIX-whole.ply and PREFIX-tiled.ply (small pieces
// removed from each, not simplified) for `lasgen --scene deck --measure`. Also says whether the
// survey made from the tiles (sheet_survey_part, combined_survey) is the whole grid's. With
// --thin, both meshes have the thin parts meshed at half the cell and joined to the sheet, as
// lasmesh does by default (finest_sheet_in_tiles: the whole grid's as one tile, and the tiles'),
// and it says whether the tiles find the whole grid's thin cells and sample the seam's corners
// as the whole grid does. Without --thin, it says whether the whole grid's sheet in the tiles'
// order (in_tile_order) is the tiles' sheet array for array.
//
// Usage: tile_sheets_bench INPUT.las TILE HALO PREFIX [--thin]
#include "build_steps.hpp"
#include "grid/thin_parts.hpp"
#include "io/ply_writer.hpp"
#include "lasmesh/build_mesh.hpp"
#include "lasmesh/mesh_pieces.hpp"
#include "mesh/marching_cubes.hpp"
#include "mesh/outside_space.hpp"
#include "mesh/surface_sheet.hpp"
#include "mesh/tiled_sheet.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <map>
#include <string>
#include <tuple>
#include <unordered_map>

using namespace lasmesh;

namespace {

// A line of /proc/self/status ("VmRSS:", "VmHWM:") in MB (0 where there is none).
double status_mb(const char* field) {
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return 0;
    char line[256];
    double kb = 0;
    while (std::fgets(line, sizeof line, f))
        if (std::string(line).rfind(field, 0) == 0) kb = std::atof(line + std::strlen(field));
    std::fclose(f);
    return kb / 1024;
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

// How two samplings of the same seam corners differ: corners whose value and normal are not the
// other's, nor both negated (a tile facing the other way: SeamFaces signs each corner itself),
// those negated, and those whose flags differ (a rejected crossing to the next corner: where a
// tile's planes face otherwise than the whole grid's, that crossing can be judged otherwise).
struct SampleDifferences {
    std::size_t other = 0, negated = 0, flags = 0;
};
SampleDifferences sample_differences(const SeamCorners& a, const SeamCorners& b) {
    SampleDifferences d;
    for (std::size_t i = 0; i < a.corners.size(); ++i) {
        const auto& n = a.normal[i];
        const auto& m = b.normal[i];
        d.flags += a.flags[i] != b.flags[i];
        if (a.value[i] == b.value[i] && n == m) continue;
        if (a.value[i] == -b.value[i] && n[0] == -m[0] && n[1] == -m[1] && n[2] == -m[2])
            ++d.negated;
        else
            ++d.other;
    }
    return d;
}

// Both meshes with their thin parts joined (--thin): the whole grid's as one tile, and the tiles'.
void meshes_with_thin_parts(const std::string& input, const CellGrid& grid, double iso,
                            const std::vector<std::array<std::int64_t, 4>>& windows, const TilePart& part_of,
                            const SheetSurvey& survey, const TiledSurvey& tiles, Mesh& whole, Mesh& tiled) {
    const std::vector<std::array<std::int64_t, 3>> thin = thin_cells(grid, iso);
    std::printf("thin cells: whole grid %zu, tiles %zu, %s\n", thin.size(), tiles.thin.size(),
                thin == tiles.thin ? "the same" : "NOT the same");
    RunReport r;
    const std::optional<ThinReadPlan> plan = plan_thin_read(tiles.thin, grid.spec, grid.axes, r);
    if (!plan) {
        std::printf("no thin parts refined: %s\n", r.thin_unrefined.c_str());
        std::exit(1);
    }
    BuildObserver quiet;
    const Refinement refined = read_thin_parts(*plan, {input}, {}, BuildOptions{}, quiet, r);
    const std::vector<std::array<std::int64_t, 4>> one{{0, grid.spec.dims[0], 0, grid.spec.dims[1]}};
    const std::array<std::int64_t, 3> dims{grid.spec.dims[0], grid.spec.dims[1], grid.spec.dims[2]};
    const TilePart all = [&](const std::array<std::int64_t, 4>&) {
        return bricks_within(grid, 0, dims[0], 0, dims[1]);
    };
    SeamCorners by_whole = seam_corners_of(refined.cells, dims), by_tiles = by_whole;
    sheets_of_tiles(grid.spec, one, all, iso, survey, &by_whole);
    sheets_of_tiles(grid.spec, windows, part_of, iso, tiles.survey, &by_tiles);
    const SampleDifferences d = sample_differences(by_whole, by_tiles);
    std::printf("seam: %zu corners; the tiles' samples: %zu not the whole grid's, %zu negated, %zu with other "
                "flags\n",
                by_whole.corners.size(), d.other, d.negated, d.flags);
    for (auto [name, windows_of, part, survey_of, mesh] :
         {std::tuple{"whole", &one, &all, &survey, &whole},
          std::tuple{"tiled", &windows, &part_of, &tiles.survey, &tiled}}) {
        TiledFinest f = finest_sheet_in_tiles(grid.spec, *windows_of, *part, iso, true, *survey_of, &refined);
        std::printf("%s: seam %.3g of %.3g of border left open (%zu stretches joined)\n", name, f.seam->open_after,
                    f.seam->open_before, f.seam->joined);
        *mesh = std::move(f.mesh);
    }
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 5) {
        std::fprintf(stderr, "usage: tile_sheets_bench INPUT.las TILE HALO PREFIX [--thin]\n");
        return 2;
    }
    const std::string input = argv[1], prefix = argv[4];
    const std::int64_t tile = std::atoll(argv[2]), halo = std::atoll(argv[3]);
    const bool thin = argc > 5 && std::string(argv[5]) == "--thin";
    const AccumulatedInputs accumulated = accumulate_inputs({input}, BuildOptions{});
    const CellGrid& grid = accumulated.accumulation->grid;
    const double iso = automatic_iso(grid), cell = grid.spec.cell_size;
    std::printf("grid %u x %u x %u cells of %.4f, iso %.1f; tiles of %lld cells, halo %lld\n", grid.spec.dims[0],
                grid.spec.dims[1], grid.spec.dims[2], cell, iso, static_cast<long long>(tile),
                static_cast<long long>(halo));
    std::unordered_map<std::uint64_t, std::uint32_t> whole_at, tiled_at;
    Mesh whole, tiled;
    const SheetSurvey survey = sheet_survey(grid, iso);
    // The same survey from the tiles, each with its halo: the noise and the outside must be the whole grid's.
    const std::vector<std::array<std::int64_t, 4>> windows = tile_windows(grid.spec, tile);
    const TilePart part_of = [&](const std::array<std::int64_t, 4>& w) {
        return bricks_within(grid, w[0] - halo, w[1] + halo, w[2] - halo, w[3] + halo);
    };
    const TiledSurvey tiled_survey = survey_tiles(grid.spec, windows, part_of, iso, thin);
    const SheetSurvey& from_tiles = tiled_survey.survey;
    std::printf("survey from the tiles: noise %s (%.3g), outside %s\n",
                from_tiles.noise == survey.noise ? "the whole grid's" : "NOT the whole grid's", from_tiles.noise,
                *from_tiles.outside == *survey.outside ? "the whole grid's" : "NOT the whole grid's");
    {
        // What the tiles hand on to face their planes together, and what comes back.
        std::size_t planes = 0;
        std::vector<UnfacedPlanes> unfaced;
        for (const auto& w : windows)
            if (const CellGrid part = part_of(w); !part.cells.empty()) {
                unfaced.push_back(unfaced_planes(part, iso, from_tiles, w));
                planes += unfaced.back().key.size();
            }
        // The facing's own memory: the peak resident set over it (reset first) less the set before.
        std::FILE* reset = std::fopen("/proc/self/clear_refs", "w");
        if (reset) std::fputs("5", reset), std::fclose(reset);
        const double before = status_mb("VmRSS:");
        const auto start = std::chrono::steady_clock::now();
        const PlaneFacing facing = plane_facing(std::move(unfaced), grid.spec, from_tiles);
        const std::chrono::duration<double> facing_time = std::chrono::steady_clock::now() - start;
        const double peak = status_mb("VmHWM:");
        const std::size_t bytes = sizeof(std::uint64_t) * 2 + sizeof(double) * 6 + sizeof(float);
        std::printf("planes handed on: %zu (%.1f MB), %zu turned, faced together in %.2f s, peaking %.1f MB over "
                    "them; the grid's cells %.1f MB\n",
                    planes, double(planes * bytes) / 1e6, facing.turned.size(), facing_time.count(), peak - before,
                    double(grid.cells.size() * sizeof(CellSums)) / 1e6);
    }
    if (thin) {
        Mesh whole_thin, tiled_thin;
        meshes_with_thin_parts(input, grid, iso, windows, part_of, survey, tiled_survey, whole_thin, tiled_thin);
        append_welded(whole, whole_at, whole_thin, [](const auto&) { return true; });
        append_welded(tiled, tiled_at, tiled_thin, [](const auto&) { return true; });
    } else {
        const auto start = std::chrono::steady_clock::now();
        const Mesh whole_sheet = extract_sheet(grid, iso);
        const auto between = std::chrono::steady_clock::now();
        const Mesh tiled_sheet = sheets_of_tiles(grid.spec, windows, part_of, iso, from_tiles);
        const std::chrono::duration<double> one = between - start, tiles = std::chrono::steady_clock::now() - between;
        std::printf("wall: the whole grid's sheet %.2f s, the tiles' (their survey made already) %.2f s\n", one.count(),
                    tiles.count());
        const Mesh ordered = in_tile_order(Mesh(whole_sheet), grid.spec, tile);
        std::printf("the whole grid's sheet in the tiles' order (in_tile_order) %s the tiles' sheet\n",
                    ordered.triangles == tiled_sheet.triangles && ordered.positions == tiled_sheet.positions &&
                            ordered.colors == tiled_sheet.colors && ordered.normals == tiled_sheet.normals
                        ? "is, array for array,"
                        : "is NOT");
        append_welded(whole, whole_at, whole_sheet, [](const auto&) { return true; });
        append_welded(tiled, tiled_at, tiled_sheet, [](const auto&) { return true; });
    }
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
                windows.size(), only_whole.size(), turned, only_tiled.size());
    for (Mesh* m : {&whole, &tiled}) {
        m->origin = grid.spec.origin, m->cell_size = cell;
        remove_small_pieces(*m, MinPiece{});
    }
    write_ply(whole, prefix + "-whole.ply");
    write_ply(tiled, prefix + "-tiled.ply");
}
