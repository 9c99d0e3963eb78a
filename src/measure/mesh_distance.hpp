// SPDX-License-Identifier: Apache-2.0
// Distances between a mesh and points: exact point-triangle distance, and nearest-neighbour
// searches through a bounding volume hierarchy. Coordinates are in the mesh's local frame.
#pragma once

#include "lasmesh/mesh.hpp"
#include "read/las_header.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace lasmesh {

using Point3f = std::array<float, 3>;

// The exact Euclidean distance from p to the closed triangle abc (degenerate triangles too).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// A bounding volume hierarchy over items (triangles or points): a binary tree of boxes split
// at the median along the longest axis, with a few items in each leaf. Near queries visit a
// handful of boxes, and far ones (outliers metres away) only a few more.
struct Bvh {
    struct Node {
        std::array<float, 3> lo, hi;
        std::uint32_t first = 0; // leaf: first item; inner node: index of the left child (right is next)
        std::uint32_t count = 0; // items in a leaf; 0 for an inner node
    };
    std::vector<Node> nodes;
    std::vector<std::uint32_t> items;
};

// Nearest triangle of a mesh, for any query point.
class TriangleSearch {
  public:
    explicit TriangleSearch(const Mesh& mesh); // the mesh must outlive the search
    // +infinity when the mesh has no triangles. `hint`: see PointSearch::distance.
    double distance(const Vec3& p, std::uint32_t* hint = nullptr) const;

  private:
    const Mesh& mesh_;
    Bvh tree_;
};

// Nearest of a set of points, for any query point.
class PointSearch {
  public:
    explicit PointSearch(std::vector<Point3f> points);
    // +infinity when there are no points. `hint` (optional, in and out): the index of the
    // nearest item of a previous query close by, updated to this query's; it only speeds up.
    double distance(const Vec3& p, std::uint32_t* hint = nullptr) const;
    std::size_t size() const { return points_.size(); }
    Vec3 point(std::size_t i) const { return {points_[i][0], points_[i][1], points_[i][2]}; }

  private:
    std::vector<Point3f> points_;
    Bvh tree_;
};

// `count` points spread over the mesh surface in proportion to area: stratified along the
// triangles' cumulative area and placed inside each triangle by a hash of the sample index,
// so the same mesh always gives the same samples.
std::vector<Vec3> sample_surface(const Mesh& mesh, std::size_t count);

} // namespace lasmesh
