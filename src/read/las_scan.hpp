// SPDX-License-Identifier: Apache-2.0
// One pass over every record: the facts a scan of the records reports, computed from the records
// themselves rather than taken from the header.
#pragma once

#include "lasmesh/las_reader.hpp"
#include "read/las_point.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

namespace lasmesh {

struct ScanResult {
    std::uint64_t point_count = 0;
    Vec3 min{}; // bounds of the decoded positions; all zero when there are no points
    Vec3 max{};
    bool has_color = false;
    Rgb16 color_min{}; // the stored 16-bit words; all zero without colour or points
    Rgb16 color_max{};
};

// Reads every remaining record of `reader` in chunks of at most `chunk_records` records.
ScanResult scan_points(LasReader& reader, std::size_t chunk_records = 1 << 16);

// A scan for the real bounds, before a second pass grids the file: throws Error (usage, option
// "scan_bounds") unless `input` is a regular file (a pipe's bytes are gone after one pass).
// check_rereadable makes that check alone, before anything is read.
void check_rereadable(const std::string& input);
ScanResult scan_file(const std::string& input);

} // namespace lasmesh
