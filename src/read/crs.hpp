// SPDX-License-Identifier: Apache-2.0
// The coordinate reference system a LAS file declares, identified by PROJ: from the OGC WKT VLR
// (LASF_Projection 2112, LAS 1.4) or the GeoTIFF keys (LASF_Projection 34735, with the doubles of
// 34736 and the text of 34737; LAS 1.0-1.4).
#pragma once

#include "lasmesh/las_reader.hpp"

#include <optional>
#include <string>

namespace lasmesh {

struct CrsInfo {
    std::string source;     // "OGC WKT" or "GeoTIFF keys"
    std::string name;       // "NAD83 / Oregon GIC Lambert (ft)"; empty when PROJ cannot read it
    std::string code;       // "EPSG:2992" when PROJ finds one; else empty
    std::string kind;       // "projected", "geographic", "geocentric" or "other" (of the horizontal part)
    std::string unit;       // the horizontal unit: "metre", "foot", "US survey foot", "degree"
    double unit_metres = 0; // metres per horizontal unit; 0 for an angle
    std::string vertical;   // the vertical CRS's name, when the file gives one
    std::string vertical_unit;
    double vertical_unit_metres = 0;
    std::string wkt;     // PROJ's WKT2 of the whole CRS, for outputs; empty when unread
    std::string problem; // why PROJ could not read it ("user-defined projection ..."), or empty

    bool identified() const { return !name.empty(); }
    bool geographic() const { return kind == "geographic"; }
};

// The CRS of a file from its header's VLRs (read_las_header keeps their payloads); nullopt when
// the file declares none. Where the file gives both, the WKT is used when the header's global
// encoding says so (bit 4, LAS 1.4), else the GeoTIFF keys. A CRS PROJ cannot read comes back
// with `problem` set, not as an error: a file is still meshed in its own units.
std::optional<CrsInfo> read_crs(const LasHeader& header);

// One line for people: "NAD83 / Oregon GIC Lambert (ft) (EPSG:2992), projected, in foot (0.3048 m);
// vertical NAVD88 height (ftUS), in US survey foot", or what could not be read.
std::string crs_summary(const CrsInfo& crs);

// What the outputs record: the EPSG code when there is one, else PROJ's WKT (one line).
std::string crs_for_outputs(const CrsInfo& crs);

} // namespace lasmesh
