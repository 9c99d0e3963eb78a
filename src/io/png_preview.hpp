// SPDX-License-Identifier: Apache-2.0
// A picture of a mesh without a viewer: four views (from above, the front, the side, and at an
// angle) rendered on the CPU and written as a PNG, for reports and for people with no 3D program.
#pragma once

#include "lasmesh/mesh.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace lasmesh {

struct PreviewImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb; // width * height pixels, 3 bytes each, rows from the top
};

// Renders `mesh` into a width x height image of 2 x 2 panels: top (looking down z), front
// (looking along +y), side (looking along -x) and an oblique view (from the south-west, 30
// degrees up). Orthographic, each panel fitted to the mesh's extent in it, a depth buffer, each
// vertex lit by a light over the viewer's shoulder on both faces (sheets are seen from both sides),
// in its colour or a neutral grey. Deterministic: the same pixels for any thread count.
PreviewImage render_preview(const Mesh& mesh, int width = 1600, int height = 1200);

// The image as PNG bytes (libpng); throws Error (output).
std::string encode_png(const PreviewImage& image);

} // namespace lasmesh
