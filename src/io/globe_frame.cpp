// SPDX-License-Identifier: Apache-2.0
#include "io/globe_frame.hpp"

#include "lasmesh/error.hpp"

#include <cmath>
#include <numbers>

namespace lasmesh {

GlobeFrame::GlobeFrame(const CrsInfo& crs, const Vec3& centre)
    : to_ecef_(std::make_unique<CrsTransform>(crs, crs_from_text("EPSG:4978"), "the tileset's frame")) {
    const CrsTransform to_geographic(crs, crs_from_text("EPSG:4979"), "the tileset's frame");
    double x = centre[0], y = centre[1], z = centre[2];
    if (to_geographic.apply(&x, &y, &z, 1) != 1)
        throw Error(ErrorKind::input, "the data's centre lies outside the area of its coordinate system");
    longitude_ = x, latitude_ = y; // x first: longitude
    double ox = centre[0], oy = centre[1], oz = centre[2];
    if (to_ecef_->apply(&ox, &oy, &oz, 1) != 1)
        throw Error(ErrorKind::input, "the data's centre lies outside the area of its coordinate system");
    origin_ = {ox, oy, oz};
    const double lambda = longitude_ * std::numbers::pi / 180, phi = latitude_ * std::numbers::pi / 180;
    east_ = {-std::sin(lambda), std::cos(lambda), 0};
    north_ = {-std::sin(phi) * std::cos(lambda), -std::sin(phi) * std::sin(lambda), std::cos(phi)};
    up_ = {std::cos(phi) * std::cos(lambda), std::cos(phi) * std::sin(lambda), std::sin(phi)};
    for (int r = 0; r < 3; ++r) {
        matrix_[0 + r] = east_[r];
        matrix_[4 + r] = north_[r];
        matrix_[8 + r] = up_[r];
        matrix_[12 + r] = origin_[r];
    }
    matrix_[15] = 1;
}

void GlobeFrame::to_frame(std::vector<Vec3>& points) const {
    std::vector<double> x(points.size()), y(points.size()), z(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) x[i] = points[i][0], y[i] = points[i][1], z[i] = points[i][2];
    if (to_ecef_->apply(x.data(), y.data(), z.data(), points.size()) != points.size())
        throw Error(ErrorKind::input, "a vertex of the mesh lies outside the area of its coordinate system");
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double d[3] = {x[i] - origin_[0], y[i] - origin_[1], z[i] - origin_[2]};
        points[i] = {east_[0] * d[0] + east_[1] * d[1] + east_[2] * d[2],
                     north_[0] * d[0] + north_[1] * d[1] + north_[2] * d[2],
                     up_[0] * d[0] + up_[1] * d[1] + up_[2] * d[2]};
    }
}

void mesh_to_frame(Mesh& mesh, const GlobeFrame& frame) {
    const std::size_t n = mesh.positions.size();
    const double step = mesh.cell_size > 0 ? mesh.cell_size : 1; // along each normal, then normalised
    std::vector<Vec3> points(mesh.normals.empty() ? n : 2 * n);
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) points[i][a] = mesh.origin[a] + mesh.positions[i][a];
        if (!mesh.normals.empty())
            for (int a = 0; a < 3; ++a) points[n + i][a] = points[i][a] + step * mesh.normals[i][a];
    }
    frame.to_frame(points);
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) mesh.positions[i][a] = static_cast<float>(points[i][a]);
        if (!mesh.normals.empty()) {
            const Vec3 d{points[n + i][0] - points[i][0], points[n + i][1] - points[i][1],
                         points[n + i][2] - points[i][2]};
            const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int a = 0; a < 3; ++a) mesh.normals[i][a] = static_cast<float>(length > 0 ? d[a] / length : 0);
        }
    }
    mesh.origin = {0, 0, 0};
}

} // namespace lasmesh
