// SPDX-License-Identifier: Apache-2.0
// Extraction of one sheet per scanned surface, placed where the points are, from the grid's
// per-cell point moments (no point is kept after accumulation).
#pragma once

#include "grid/cell_sums.hpp"
#include "lasmesh/mesh.hpp"
#include "lasmesh/surface.hpp"
#include "mesh/outside_space.hpp"
#include "mesh/seam_corners.hpp"

#include <functional>
#include <memory>

namespace lasmesh {

// The surface the points define, after Hoppe et al. 1992 ("Surface reconstruction from
// unorganized points"), with the grid's cells standing in for the points' neighbourhoods:
//  1. every cell with more than `iso` points is a surface cell, with a tangent plane through its
//     points' centroid (exact, from the position sums) and a normal from the principal axes of
//     the centroids of the surface cells around it (3 x 3 x 3); each plane (not a tube's) then
//     moved along its normal to the mean of the layer of points it shares with the cells across
//     it, which a cell face splits into tails whose centroids sit off the surface;
//  2. the normals are oriented consistently by growing a maximum spanning tree over neighbouring
//     cells, weighted by how parallel their planes are, and linking only cells that lie along each
//     other's plane (so the two faces of a wall thicker than a cell keep opposite normals, and a
//     plate thinner than one, one sheet for both faces, orients nothing beyond itself); the side
//     each faces is the outside, as found by flooding a coarse voxel grid from above (the inside
//     of a box, a pipe or a sphere is never reached), else outward or up;
//  3. a signed distance is sampled at the cell corners next to surface cells: the distance to the
//     plane of the nearest centroid among the corner's eight cells;
//  4. marching cubes over the corner samples, rejecting crossings between planes that are not the
//     same surface (opposite normals, or more than two cells apart), so junctions and the ends of thin parts
//     leave boundaries rather than stray sheets.
// With LinearParts::tubes, a surface cell whose surface cells around it (5 x 5 x 5) lie along a
// line is on a tube (a rail, a post, a thin pipe): its samples are the distance to a cylinder round
// that line, of the radius the cells' centroids give (at least the lattice's smallest: half a
// cell's diagonal); a cell on or in tubes around it without being one (where a rail meets a post, a
// tube's end; not a plane across their axes, as the deck under a post) samples their union;
// crossings join tubes to tubes only. For grids fine enough that
// such parts are a few cells across (the thin parts' grid of half the cell); at coarser cells a
// rail is a line of single cells, and its tube would be the lattice's smallest, not its own.
// A scan's layer of occupied cells, one or two cells thick, becomes one sheet through its points
// instead of two sheets around it; where the grid holds its cells' moments and a layer's points
// spread along its normal well past the scan's noise (a plate thinner than a cell, scanned on
// both faces), that sheet is split into the plate's two faces, each half the estimated
// thickness from the middle. The sheets are open where the surface ends; their triangles face
// along the oriented normals; vertex normals are the planes' normals (a tube's: away from its axis)
// and vertex colours the cells' mean colours, both interpolated along the edge. Each connected part
// of the result is turned, if need be, to face the outside.
//
// Where a finer sheet's mesh is kept in some of the grid's cells (the thin parts, joined by
// seam.hpp's append_joined), the finer sheet ends on those cells' faces where this one does:
// `coarse_seam`, when given, is called (and may wait) once the finer sheet's planes are made,
// and gives this sheet's samples at the cells' corners (SeamRequest below), which the finer
// sheet takes on the faces between those cells and the others (SeamFaces).
enum class LinearParts { planes, tubes };
Mesh extract_sheet(const CellGrid& grid, double iso, LinearParts linear = LinearParts::planes,
                   const std::function<const SeamCorners&()>& coarse_seam = {});
// The coarse side of a seam: the sheet's samples at `corners`' corners (seam_corners_of), made
// and handed to `sampled` (on this thread) before the sheet is marched.
struct SeamRequest {
    SeamCorners corners;
    std::function<void(SeamCorners&&)> sampled;
};
// The same, releasing the grid's cells as soon as the planes are made (the grid keeps its
// geometry and index, its cells are empty afterwards): the grid's memory and the mesh's never
// add up. `released`, when given, is called then, on this thread: a caller may start work
// that needs the memory (build_mesh starts the second read of the thin parts there).
Mesh extract_sheet(CellGrid&& grid, double iso, LinearParts linear = LinearParts::planes,
                   const std::function<void()>& released = {}, SeamRequest* seam = nullptr);

// What the sheet takes from the whole grid rather than from the cells around each plane: the
// scan's noise (the median spread of the layers' points along their normals, against which a
// plate's two faces are told) and the space outside every surface (which way each piece faces).
// The rest looks a few cells around each cell, so a part of the grid (some of its bricks, with
// the grid's size and origin) meshed with the whole grid's SheetSurvey gives the whole grid's
// sheet there, but for which way its planes and its connected parts face, which look at whole
// pieces (plane_facing below, and tile_facing.hpp): tiles can be meshed one by one, each with a
// halo of cells round it, and their sheets joined (tiled_sheet.hpp; docs/design.md, "Over many
// machines").
struct SheetSurvey {
    double noise = 0; // a variance, in the grid's units squared; 0: none measured (no plate is split)
    std::shared_ptr<const OutsideSpace> outside;
};
SheetSurvey sheet_survey(const CellGrid& grid, double iso, LinearParts linear = LinearParts::planes);
// The same from parts of the grid (tiles, each with a halo of 8 cells or more round it), each
// read on its own: a part's share is its own planes' layers' spreads (those whose cell lies in
// `own`: x from own[0] to own[1], y from own[2] to own[3], in the grid's cells) and one of its own
// surface cells for each of the outside's voxels that holds some. Combined over parts that
// cover the grid, it is the whole grid's survey: the same noise (the median of the same spreads)
// and the same outside.
struct SurveyPart {
    std::vector<double> spreads;
    std::vector<std::array<std::int64_t, 3>> walls; // ascending
};
SurveyPart sheet_survey_part(const CellGrid& part, double iso, const std::array<std::int64_t, 4>& own,
                             LinearParts linear = LinearParts::planes);
SheetSurvey combined_survey(const std::vector<SurveyPart>& parts, const std::array<std::uint32_t, 3>& dims);
// A part's sheet with the whole grid's survey; `seam`, when given, is sampled as the
// SeamRequest of the extraction above (a tile's share of the seam's corners: tiled_sheet.hpp).
Mesh extract_sheet(const CellGrid& part, double iso, const SheetSurvey& survey,
                   LinearParts linear = LinearParts::planes, SeamRequest* seam = nullptr);

// The one step of the sheet that a part cannot take from its cells and a halo round them is which
// way its planes face (step 2: a spanning tree over the whole grid's planes, each piece facing the
// way most of it sees the outside). A part hands on its planes before they are faced, those whose
// cell lies in `window` (x from window[0] to window[1], y from window[2] to window[3]): fewer
// bytes than the cells (surface cells only, a place, normal and count against a cell's sums and
// moments: three fifths of them on the generated decks), and orienting them is one pass of the
// tree. With a halo of 8 cells or more round
// each part, the parts' planes are the whole grid's, and plane_facing orients them as the whole
// grid's sheet does, bit for bit.
struct UnfacedPlanes {
    std::vector<std::uint64_t> key; // the cell's CellGrid::order_key, ascending
    std::vector<std::array<double, 3>> centroid, normal;
    std::vector<std::uint64_t> count;
    std::vector<float> half_thickness; // a plate's two faces apart, halved (empty: no plate found)
};
UnfacedPlanes unfaced_planes(const CellGrid& part, double iso, const SheetSurvey& survey,
                             const std::array<std::int64_t, 4>& window, LinearParts linear = LinearParts::planes);
// The order keys of the planes that face against the normal their cells' points give (ascending).
struct PlaneFacing {
    std::vector<std::uint64_t> turned;
};
// The parts' planes together (the parts' windows apart), oriented as the whole grid's sheet
// orients its planes; each part is freed once taken in.
PlaneFacing plane_facing(std::vector<UnfacedPlanes> parts, const GridSpec& grid, const SheetSurvey& survey);
// A part's sheet with its planes faced as `facing` says (those it does not name face along their
// points' normal), marched, its vertex normals agreeing with its faces; before its connected parts
// are turned to face the outside (step 5, which needs the whole sheet's parts: tile_facing.hpp)
// and plates' sheets split into their two faces (split_two_faces, with `half`).
struct FacedSheet {
    Mesh mesh;
    std::vector<float> half; // per vertex, for split_two_faces (empty: no plate)
};
FacedSheet faced_sheet(const CellGrid& part, double iso, const SheetSurvey& survey, const PlaneFacing& facing,
                       LinearParts linear = LinearParts::planes, SeamRequest* seam = nullptr);
// Each triangle with a vertex whose `half` is over 0 (a plate's) gets a copy for the plate's back
// face, `half` behind it along the vertex normals and facing the other way; the front face moves
// `half` forward. The last step of the sheet.
void split_two_faces(Mesh& mesh, const std::vector<float>& half);

} // namespace lasmesh
