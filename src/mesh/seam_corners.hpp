// SPDX-License-Identifier: Apache-2.0
// SeamCorners: the coarse sheet's samples at the corners of the refined cells, so that the fine
// sheet ends on the seam's faces where the coarse one does.
//
//     SeamCorners c = seam_corners_of(refined_cells, grid_dims); // the corners to sample
//     ... the coarse sheet fills c.value, c.normal, c.flags (extract_sheet's SeamRequest) ...
//     const SeamFaces faces(c);
//     float v;
//     switch (faces.coarse_value(x, y, z, fine_normal, v)) { ... } // at a fine lattice point
#pragma once

#include "grid/cell_set.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace lasmesh {

// The corners of a set of a grid's cells, and the grid's sheet sampled there.
struct SeamCorners {
    std::array<std::int64_t, 3> dims{};       // the grid's cells an axis
    std::vector<std::uint64_t> refined;       // the cells ((z * dims[1] + y) * dims[0] + x), ascending
    std::vector<std::uint64_t> corners;       // their corners' lattice keys (dims + 1 points an axis), ascending
    std::vector<float> value;                 // per corner: the sheet's signed distance there
    std::vector<std::array<float, 3>> normal; // the normal of the plane that decided it
    // Per corner: bit 0, the sample is defined; bit 1 + a, the sheet rejects the crossing on the
    // lattice edge from it along axis a (its samples on opposite sides, of surfaces that do not meet).
    std::vector<std::uint8_t> flags;

    static constexpr std::uint8_t defined = 1;
    std::array<std::int64_t, 3> corner_of(std::uint64_t key) const;
    std::uint64_t key_of(std::int64_t x, std::int64_t y, std::int64_t z) const;
};

// The corners of `refined` (cell keys of a grid of `dims` cells, ascending), nothing sampled yet.
SeamCorners seam_corners_of(const std::vector<std::uint64_t>& refined, const std::array<std::int64_t, 3>& dims);

// Where the grid of half the cell (on the same origin) meets the sampled one: a point of the fine
// lattice lies on the seam when among the grid's cells it touches some are refined and some not.
// There the fine sheet takes the coarse one's value, interpolated along the coarse cell's edge or
// face (the fine lattice splits them in two): the two sheets then cross every coarse edge of the
// seam at the same point, and its faces on the same curves but for the bilinear bend, so their
// borders run together and can be joined (the crack patching of Shu, Zhou & Kankanhalli 1995,
// "Adaptive marching cubes", made by the field rather than by moving the border afterwards).
class SeamFaces {
  public:
    explicit SeamFaces(const SeamCorners& corners);

    enum class Found { off_seam, undefined, value };
    // At fine lattice point (x, y, z) whose fine sample has the plane normal `normal` (unit):
    // off_seam off the seam, or on it where the coarse sheet runs across the fine plane (normals
    // over 60 degrees apart) rather than along it; undefined where the coarse sheet is undefined
    // or rejects a crossing of the edge or face the point lies on (whatever the normals); else
    // the coarse value, each corner's signed the way the fine normal faces (the two sheets are
    // oriented each on its own).
    Found coarse_value(std::int64_t x, std::int64_t y, std::int64_t z, const std::array<double, 3>& normal,
                       float& value) const;

  private:
    bool refined(std::int64_t x, std::int64_t y, std::int64_t z) const;
    const SeamCorners& c_;
    CellSet cells_;
};

} // namespace lasmesh
