// SPDX-License-Identifier: Apache-2.0
// The grid the points are counted into: cubic cells over the cloud's bounds, and the exact rule
// that assigns a point to a cell, decided once in raw LAS integers so every device agrees.
#pragma once

#include "lasmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lasmesh {

struct Bounds {
    Vec3 min{};
    Vec3 max{};
};

// What the user asked for: a grid chosen from the data (the default, as `lasmesh --grid auto`),
// N cells along the longest axis, NX x NY x NZ cells, or a cell edge. Build one with the named
// constructors: GridRequest::longest(512), GridRequest::cells(512, 256, 128), GridRequest::cell_edge(0.05).
struct GridRequest {
    enum class Kind { automatic, longest_axis, explicit_dims, voxel_size } kind = Kind::automatic;
    std::array<std::uint32_t, 3> dims{0, 0, 0}; // longest_axis uses dims[0]
    double voxel = 0;                           // voxel_size: cell edge in file units

    static GridRequest longest(std::uint32_t n) { return {Kind::longest_axis, {n, 0, 0}, 0}; }
    static GridRequest cells(std::uint32_t nx, std::uint32_t ny, std::uint32_t nz) {
        return {Kind::explicit_dims, {nx, ny, nz}, 0};
    }
    static GridRequest cell_edge(double edge) { return {Kind::voxel_size, {0, 0, 0}, edge}; }
};

// Cubic cells of edge `cell_size`; cell (i, j, k) spans origin + [i, i+1) * cell_size on x (and
// likewise y, z), except that the last cell on each axis is closed: a point exactly on the upper
// face belongs to it. Cells are stored x fastest: index = (k * ny + j) * nx + i.
struct GridSpec {
    Vec3 origin{};
    double cell_size = 1;
    std::array<std::uint32_t, 3> dims{1, 1, 1};

    std::uint64_t cell_count() const { return std::uint64_t{dims[0]} * dims[1] * dims[2]; }
};

// The most cells along one axis, and the most bricks (4 x 4 x 4 cells) in all: the device numbers
// bricks in 32 bits, and its brick index holds a word for each brick of the grid's volume, so
// the limit that bites first is usually that index's memory (checked before the points are
// accumulated).
constexpr std::uint32_t max_grid_cells = 16384;
constexpr std::uint64_t max_grid_bricks = std::uint64_t{1} << 31;
// Whether `grid` numbers its bricks within max_grid_bricks.
bool within_brick_numbers(const GridSpec& grid);

// Covers `bounds` with cubic cells as requested, the bounds centred with at least half a cell to
// spare on every side (so points on the bounds, such as a flat scan's plane, lie inside cells):
// N cells along the longest axis are cells of its extent / (N - 1); a cell edge h gives
// ceil(extent / h) + 1 cells per axis; explicit dims keep their counts with the smallest cell
// that leaves the half cells. A flat or single-point cloud still gets a valid grid (cells of 1
// unit when every extent is zero). Throws Error (usage) past max_grid_cells on an axis.
GridSpec make_grid_spec(const Bounds& bounds, const GridRequest& request);

} // namespace lasmesh
