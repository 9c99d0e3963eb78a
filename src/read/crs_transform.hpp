// SPDX-License-Identifier: Apache-2.0
// Coordinates from one CRS into another with PROJ, x first (east, or longitude) whatever order
// the CRS's definition gives its axes; the CRS a user names; and the CRS a survey in longitude
// and latitude is meshed in: the UTM zone of its centre, on its own datum.
#pragma once

#include "lasmesh/grid.hpp"
#include "read/crs.hpp"

#include <cstddef>
#include <memory>
#include <string>

namespace lasmesh {

// "EPSG:32631" (any AUTHORITY:CODE PROJ's database holds), a WKT or a PROJJSON text; throws Error
// (usage, option "crs") when PROJ cannot make a CRS of it.
CrsInfo crs_from_text(const std::string& text);

// The UTM zone around (longitude, latitude) in degrees (with the Norway and Svalbard exceptions),
// north or south of the equator by the latitude, on the datum of `geographic` and keeping its
// vertical CRS: WGS 84 / UTM zone 31N (EPSG:32631) for a WGS 84 survey at 2 E, 50 N.
CrsInfo utm_crs_for(const CrsInfo& geographic, double longitude, double latitude);

class CrsTransform {
  public:
    // Throws Error (input) naming `file` and both CRSs when PROJ has no transformation between them.
    CrsTransform(const CrsInfo& from, const CrsInfo& to, const std::string& file);
    ~CrsTransform();
    CrsTransform(const CrsTransform&) = delete;
    CrsTransform& operator=(const CrsTransform&) = delete;

    // Transforms n points in place; returns n, or the index of the first point PROJ could not
    // transform (outside the area where the CRS is defined).
    std::size_t apply(double* x, double* y, double* z, std::size_t n) const;
    // A box holding the transform of every point of `box` (its edges followed, not just its corners).
    // Throws Error (input) naming the file when the box lies outside the CRS's area.
    Bounds bounds(const Bounds& box) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace lasmesh
