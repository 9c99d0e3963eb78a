// SPDX-License-Identifier: Apache-2.0
// A local east-north-up frame at a point on the Earth, where 3D Tiles places a tileset: positions
// in the survey's CRS go through PROJ into Earth-centred, Earth-fixed coordinates (ECEF, WGS 84,
// EPSG:4978), then into the frame whose origin is the point and whose axes point east, north and
// up (the ellipsoid's normal). The tileset's root transform is the frame's matrix and the tiles'
// positions stay small, float32 precise. A projected grid is not east-north-up (in UTM the grid
// north turns from true north by the meridian convergence, a degree 70 km off the central meridian
// at 59 N), so an offset alone would misplace the mesh; PROJ's transform does not.
#pragma once

#include "lasmesh/mesh.hpp"
#include "read/crs.hpp"
#include "read/crs_transform.hpp"

#include <array>
#include <memory>
#include <vector>

namespace lasmesh {

class GlobeFrame {
  public:
    // The frame at `centre`, a point in `crs`. Throws Error (input) when PROJ cannot carry the CRS
    // to ECEF or the point lies outside the CRS's area.
    GlobeFrame(const CrsInfo& crs, const Vec3& centre);

    // Column-major 4 x 4 (3D Tiles' `transform`): frame coordinates to ECEF metres.
    const std::array<double, 16>& matrix() const { return matrix_; }
    double longitude() const { return longitude_; } // degrees, of the centre
    double latitude() const { return latitude_; }

    // Points in the CRS, in place, into the frame (metres). Throws Error (input) when PROJ fails
    // for one (outside the CRS's area).
    void to_frame(std::vector<Vec3>& points) const;

  private:
    std::unique_ptr<CrsTransform> to_ecef_;
    std::array<double, 16> matrix_{};
    Vec3 origin_{}, east_{}, north_{}, up_{};
    double longitude_ = 0, latitude_ = 0;
};

// A mesh in the CRS moved into the frame: positions (origin + local) carried by PROJ, normals
// turned with them (each through a point a small step along it), the origin set to 0.
void mesh_to_frame(Mesh& mesh, const GlobeFrame& frame);

} // namespace lasmesh
