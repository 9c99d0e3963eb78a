// SPDX-License-Identifier: Apache-2.0
// What surface is made of the grid of points, and where its vertices go: the choices
// BuildOptions::surface and BuildOptions::placement make (the command line's --surface and
// --placement).
//
//     lasmesh::BuildOptions options;
//     options.surface = lasmesh::SurfaceKind::closed;      // a watertight solid instead of sheets
//     options.placement = lasmesh::VertexPlacement::iso;   // classic marching cubes
#pragma once

namespace lasmesh {

// What extraction makes of the grid.
enum class SurfaceKind {
    sheet,  // one open sheet through the points of each surface (two for a plate scanned on both faces): the default
    closed, // a watertight surface around the occupied cells, for solids
};

// Where a vertex goes along its crossed edge.
enum class VertexPlacement {
    // At half the local layer's count : on the scanned
    // surface rather than around it. Scans put points on surfaces, so the occupied cells form a
    // thin layer that a plain level set wraps at up to a cell on each side.
    surface,
    // Classic marching cubes: linear interpolation of the counts at the iso value.
    iso,
};

} // namespace lasmesh
