// SPDX-License-Identifier: Apache-2.0
// Fidelity of a mesh to the cloud it came from, measured both ways as in the study's section 5:
// cloud to mesh (is every point near the surface?) and mesh to cloud (is the surface near the
// points, or does it invent shapes?).
#pragma once

#include "lasmesh/las_reader.hpp"
#include "lasmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace lasmesh {

struct DistanceStats {
    std::uint64_t count = 0;
    double mean = 0, std = 0, median = 0, p95 = 0, p99 = 0, max = 0;
    double within_1_cell = -1, within_2_cells = -1; // shares in [0, 1]; -1 when no cell size is known
    // The mean over the distances of at most 2 cells: how far the mesh is from the points it
    // meshed, without the outlier clusters and removed pieces that dominate the plain mean.
    double mean_within_2_cells = -1;
};

// Summary statistics of `distances` (reordered in place); percentiles are nearest-rank.
DistanceStats summarize(std::vector<double>& distances, double cell_size);

struct CompareOptions {
    std::uint64_t samples = 5'000'000;      // cloud points used at most, spread evenly over the file
    std::uint64_t mesh_samples = 1'000'000; // points sampled on the mesh surface
    double cell_size = 0;                   // 0: the mesh's own (from its file), if known
    // Called as each step starts ("reading the cloud", "cloud to mesh", ...), for a progress line.
    std::function<void(const std::string& step)> on_step;
};

struct CompareResult {
    DistanceStats cloud_to_mesh, mesh_to_cloud;
    std::uint64_t points_read = 0, points_used = 0, samples_used = 0;
    double cell_size = 0;
    std::vector<double> vertex_distance; // per mesh vertex: distance to the nearest used point
    // "WGS 84 (EPSG:4326), ... to WGS 84 / UTM zone 15N (EPSG:32615), ..." when the cloud was
    // brought into the CRS the mesh records; empty when it was measured as it is.
    std::string cloud_transformed;
};

// Streams the cloud once, keeping the selected points (relative to the mesh origin) in memory;
// a cloud whose CRS differs from the one the mesh records (Mesh::crs) is transformed into it with
// PROJ first (a mesh of a file in degrees is in UTM): lengths are then in the mesh's unit.
// memory is bounded by the mesh and `samples`, not by the file. With more points than
// `samples`, mesh-to-cloud distances are measured to that subset, so they are upper bounds.
CompareResult compare(const Mesh& mesh, LasReader& cloud, const CompareOptions& options);

// A colour ramp for heat maps: blue at 0, through cyan, green and yellow, to red at `scale`
// and beyond.
std::array<std::uint8_t, 3> heat_color(double distance, double scale);

} // namespace lasmesh
