// SPDX-License-Identifier: Apache-2.0
// Tiles' sheets made to face as one.
//
//     std::vector<TileRegions> regions;
//     for (const Mesh& sheet : tile_sheets) regions.push_back(tile_regions(sheet));
//     const std::vector<std::vector<char>> turns = facing_turns(regions);
//     for (std::size_t k = 0; k < tile_sheets.size(); ++k) turn_regions(tile_sheets[k], regions[k], turns[k]);
//
// A sheet meshed tile by tile (each tile from its own cells and a halo round them, with the whole
// grid's SheetSurvey, keeping the triangles whose centroid lies in the tile: surface_sheet.hpp)
// is the whole grid's sheet but for which way it faces: each tile orients its planes by a
// spanning tree over its own window, so a surface crossing a tile's border may face one way on
// one side and the other way on the other. What joins them is small beside the meshes: each
// tile's regions (its triangles joined across edges that two of them share running opposite
// ways, so that a region faces one way throughout) with their areas, and the edges on its border
// (used by one of its triangles). A tile can hand that on, and the turns be decided from all
// tiles' together.
#pragma once

#include "lasmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace lasmesh {

// What facing_turns needs of one tile's sheet.
struct TileRegions {
    struct BorderEdge {
        std::array<float, 3> from, to; // its ends, in its triangle's winding
        std::array<float, 3> normal;   // its triangle's unit normal, the way the winding faces
        std::uint32_t region = 0;
    };
    std::vector<std::uint32_t> of_triangle; // each triangle's region, numbered by their first triangles
    std::vector<double> area;               // each region's, in cells (of the sheet's cell size; else units)
    std::vector<BorderEdge> border;         // the edges one triangle uses, in the triangles' order
};

TileRegions tile_regions(const Mesh& sheet);

// Per tile, per region: whether to turn it (1) or not (0). Two tiles' regions that share border
// edges (the same two positions, bit for bit, their triangles within 60 degrees of one plane)
// run alike there or against each other. The regions are joined as their shared edges say, the
// pair whose edges say so by the widest margin first, a joined piece's edges to another added up
// (agglomerative, so that a small region across a fold, alike with its neighbours on one side
// and against them on the other, is outweighed by the edges of the pieces around it rather than
// deciding for them); two pieces that their tiles faced apart join only where their say is a
// tenth of the smaller's border or more (a stray edge at a plate's rim does not turn a face).
// Each joined piece keeps the way most of its area faced in its tiles. Then each region is
// turned on its own where more of its shared edges would run alike, by a tenth of its border
// more when that turns it from its tile's facing (a local search, as in correlation clustering:
// the joining is greedy). Depends on the tiles' order and
// contents only.
std::vector<std::vector<char>> facing_turns(const std::vector<TileRegions>& tiles);

// Turns the regions that `turn` names: their triangles' winding and their vertices' normals (a
// vertex of regions turned apart turns with its first triangle).
void turn_regions(Mesh& sheet, const TileRegions& regions, const std::vector<char>& turn);

} // namespace lasmesh
