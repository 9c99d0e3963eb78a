// SPDX-License-Identifier: Apache-2.0
#include "mesh/mesh_tiles.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace lasmesh {

std::vector<MeshTile> split_into_tiles(const Mesh& mesh, const Vec3& corner, double edge, std::int64_t count) {
    // The tile of each triangle, by its centroid in world coordinates.
    std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::uint32_t>> triangles_of; // (y, x)
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        double centroid[2] = {0, 0};
        for (const std::uint32_t v : mesh.triangles[t])
            for (int a = 0; a < 2; ++a) centroid[a] += mesh.positions[v][a];
        const auto cell = [&](int a) {
            const double at = std::floor((centroid[a] / 3 + mesh.origin[a] - corner[a]) / edge);
            return std::clamp(static_cast<std::int64_t>(std::clamp(at, -1.0, static_cast<double>(count))),
                              std::int64_t{0}, count - 1);
        };
        triangles_of[{cell(1), cell(0)}].push_back(t);
    }
    std::vector<MeshTile> tiles;
    std::vector<std::uint32_t> local(mesh.positions.size(), UINT32_MAX);
    for (const auto& [at, triangles] : triangles_of) {
        MeshTile tile;
        tile.y = at.first, tile.x = at.second;
        Mesh& m = tile.mesh;
        m.origin = mesh.origin, m.cell_size = mesh.cell_size, m.crs = mesh.crs;
        std::vector<std::uint32_t> used;
        for (const std::uint32_t t : triangles) {
            std::array<std::uint32_t, 3> corners{};
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = mesh.triangles[t][k];
                if (local[v] == UINT32_MAX) {
                    local[v] = static_cast<std::uint32_t>(used.size());
                    used.push_back(v);
                }
                corners[k] = local[v];
            }
            m.triangles.push_back(corners);
        }
        for (const std::uint32_t v : used) {
            m.positions.push_back(mesh.positions[v]);
            if (!mesh.colors.empty()) m.colors.push_back(mesh.colors[v]);
            if (!mesh.normals.empty()) m.normals.push_back(mesh.normals[v]);
            local[v] = UINT32_MAX;
        }
        tiles.push_back(std::move(tile));
    }
    return tiles;
}

} // namespace lasmesh
