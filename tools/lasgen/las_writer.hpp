// SPDX-License-Identifier: Apache-2.0
// Writing LAS 1.0-1.4 files of point formats 0-10, for generated scenes and test fixtures.
#pragma once

#include "scene.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lasgen {

struct LasLayout {
    int version_minor = 2;
    int point_format = 3;
    int extra_bytes = 0; // zero bytes appended to every record
    int color_bits = 8;  // 8: values 0-255 in the 16-bit fields; 16: value * 257
    Vec3 scale{0.001, 0.001, 0.001};
    Vec3 offset{};
    // GeoTIFF keys (LASF_Projection 34735) naming this EPSG CRS: 4000-4999 as a geographic CRS
    // (GeographicTypeGeoKey), others as a projected one (ProjectedCSTypeGeoKey); 0: none.
    int epsg = 0;
};

// Throws std::invalid_argument for combinations the LAS specification does not allow
// (formats 6-10 need LAS 1.4, 4-5 need 1.3, 2-3 need 1.2) and other bad values.
void validate_layout(const LasLayout& layout);

std::uint16_t record_length(const LasLayout& layout);

// Everything before the first point record: the header, one VLR naming the generator with
// `description` as its payload, and LAS 1.0's two-byte point data start signature.
std::vector<std::byte> las_file_head(const LasLayout& layout, std::uint64_t point_count, const Vec3& min,
                                     const Vec3& max, const std::string& description);

// One record for `point`; `index` fills the GPS time. Throws std::out_of_range when a coordinate
// does not fit the 32-bit integer field at this scale and offset.
void encode_record(const LasLayout& layout, const GeneratedPoint& point, std::uint64_t index, std::byte* record);

} // namespace lasgen
