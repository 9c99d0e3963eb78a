// SPDX-License-Identifier: Apache-2.0
// An indexed triangle mesh with optional per-vertex colour and normals, positions in a local frame.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lasmesh {

// A position in the input's coordinates (x, y, z in its units).
using Vec3 = std::array<double, 3>;

struct Mesh {
    // World coordinates of the local frame's origin. float32 positions cannot hold a centimetre
    // at a UTM northing of 6,700,000 m, so positions are stored relative to this point.
    Vec3 origin{};
    // Edge of the grid cell the mesh was extracted at (0: unknown). Output precision and the
    // distances of `lasmesh compare` are judged against it.
    double cell_size = 0;
    // The coordinate system of `origin` and the positions, as the input declared it: "EPSG:2992",
    // or a WKT when it has no EPSG code; empty when unknown. Every output records it.
    std::string crs;
    std::vector<std::array<float, 3>> positions;
    std::vector<std::array<std::uint8_t, 3>> colors; // one per vertex, or empty: no colour
    // Unit normals, one per vertex, or empty. They point to the side the triangles face
    // (counter-clockwise winding seen from there).
    std::vector<std::array<float, 3>> normals;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

} // namespace lasmesh
