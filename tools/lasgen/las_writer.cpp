// SPDX-License-Identifier: Apache-2.0
// LAS writing from the specification's field tables (LAS 1.4 R15, sections 2.2-2.6).
#include "las_writer.hpp"

#include "read/las_header.hpp"

#include "byte_order.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace lasgen {

using lasmesh::store_le;

void validate_layout(const LasLayout& l) {
    if (l.version_minor < 0 || l.version_minor > 4) throw std::invalid_argument("LAS version must be 1.0 to 1.4");
    if (l.point_format < 0 || l.point_format > 10) throw std::invalid_argument("point format must be 0 to 10");
    static constexpr int first_version[] = {0, 0, 2, 2, 3, 3, 4, 4, 4, 4, 4};
    if (l.version_minor < first_version[l.point_format])
        throw std::invalid_argument("point format " + std::to_string(l.point_format) + " needs LAS 1." +
                                    std::to_string(first_version[l.point_format]) + " or later");
    if (l.extra_bytes < 0 || lasmesh::core_record_size(l.point_format) + l.extra_bytes > 65535)
        throw std::invalid_argument("extra bytes must be 0 to 65535 minus the core record size");
    if (l.color_bits != 8 && l.color_bits != 16) throw std::invalid_argument("colour depth must be 8 or 16");
    for (double s : l.scale)
        if (!(s > 0) || !std::isfinite(s)) throw std::invalid_argument("scale factors must be positive");
}

std::uint16_t record_length(const LasLayout& l) {
    return static_cast<std::uint16_t>(lasmesh::core_record_size(l.point_format) + l.extra_bytes);
}

namespace {
void put_string(std::byte* at, const std::string& text, std::size_t size) {
    std::memcpy(at, text.data(), std::min(text.size(), size));
}
} // namespace

std::vector<std::byte> las_file_head(const LasLayout& l, std::uint64_t point_count, const Vec3& min, const Vec3& max,
                                     const std::string& description) {
    validate_layout(l);
    const std::uint16_t header_size = lasmesh::minimum_header_size(l.version_minor);
    const std::size_t geo_keys_size = l.epsg ? 54 + 24 : 0; // header and two keys, 4 shorts each
    const std::size_t vlr_size = 54 + description.size() + geo_keys_size;
    const std::size_t start_signature = l.version_minor == 0 ? 2 : 0;
    std::vector<std::byte> head(header_size + vlr_size + start_signature);
    std::byte* h = head.data();

    put_string(h, "LASF", 4);
    // A 1.4 file with point formats 6-10 must set the WKT bit (4) of the global encoding.
    if (l.version_minor >= 2) store_le<std::uint16_t>(h + 6, l.version_minor == 4 && l.point_format >= 6 ? 0x10 : 0);
    h[24] = std::byte{1};
    h[25] = static_cast<std::byte>(l.version_minor);
    put_string(h + 26, "lasmesh lasgen", 32);
    put_string(h + 58, "lasgen", 32);
    store_le<std::uint16_t>(h + 90, 1);    // creation day of year: fixed, so output is deterministic
    store_le<std::uint16_t>(h + 92, 2026); // creation year
    store_le<std::uint16_t>(h + 94, header_size);
    store_le<std::uint32_t>(h + 96, static_cast<std::uint32_t>(head.size()));
    store_le<std::uint32_t>(h + 100, l.epsg ? 2 : 1);
    h[104] = static_cast<std::byte>(l.point_format);
    store_le<std::uint16_t>(h + 105, record_length(l));
    // LAS 1.4 keeps the legacy counts at 0 for formats 6-10 and for counts beyond 32 bits.
    const bool legacy = l.point_format < 6 && point_count <= std::numeric_limits<std::uint32_t>::max();
    const std::uint32_t legacy_count = legacy ? static_cast<std::uint32_t>(point_count) : 0;
    store_le<std::uint32_t>(h + 107, legacy_count);
    store_le<std::uint32_t>(h + 111, legacy_count); // every generated point is a first return
    for (int a = 0; a < 3; ++a) {
        store_le<double>(h + 131 + 8 * a, l.scale[a]);
        store_le<double>(h + 155 + 8 * a, l.offset[a]);
        store_le<double>(h + 179 + 16 * a, max[a]);
        store_le<double>(h + 187 + 16 * a, min[a]);
    }
    if (l.version_minor == 4) {
        store_le<std::uint64_t>(h + 247, point_count);
        store_le<std::uint64_t>(h + 255, point_count);
    }

    std::byte* vlr = h + header_size;
    put_string(vlr + 2, "lasmesh", 16);
    store_le<std::uint16_t>(vlr + 18, 1);
    store_le<std::uint16_t>(vlr + 20, static_cast<std::uint16_t>(description.size()));
    put_string(vlr + 22, "lasgen scene", 32);
    put_string(vlr + 54, description, description.size());
    if (l.epsg) {
        const bool geographic = l.epsg >= 4000 && l.epsg < 5000;
        std::byte* keys = vlr + 54 + description.size();
        put_string(keys + 2, "LASF_Projection", 16);
        store_le<std::uint16_t>(keys + 18, 34735);
        store_le<std::uint16_t>(keys + 20, 24);
        put_string(keys + 22, "GeoTIFF GeoKeyDirectoryTag", 32);
        const std::uint16_t directory[12] = {1,
                                             1,
                                             0,
                                             2,
                                             1024,
                                             0,
                                             1,
                                             std::uint16_t(geographic ? 2 : 1),
                                             std::uint16_t(geographic ? 2048 : 3072),
                                             0,
                                             1,
                                             std::uint16_t(l.epsg)};
        for (int k = 0; k < 12; ++k) store_le<std::uint16_t>(keys + 54 + 2 * k, directory[k]);
    }
    if (start_signature) {
        head[head.size() - 2] = std::byte{0xDD};
        head[head.size() - 1] = std::byte{0xCC};
    }
    return head;
}

void encode_record(const LasLayout& l, const GeneratedPoint& p, std::uint64_t index, std::byte* r) {
    std::memset(r, 0, record_length(l));
    for (int a = 0; a < 3; ++a) {
        double raw = std::round((p.position[a] - l.offset[a]) / l.scale[a]);
        if (!(raw >= std::numeric_limits<std::int32_t>::min() && raw <= std::numeric_limits<std::int32_t>::max()))
            throw std::out_of_range("coordinate does not fit a 32-bit LAS integer at this scale and offset");
        store_le<std::int32_t>(r + 4 * a, static_cast<std::int32_t>(raw));
    }
    const std::uint16_t intensity = static_cast<std::uint16_t>((p.color[0] + p.color[1] + p.color[2]) * 85);
    store_le<std::uint16_t>(r + 12, intensity);
    const double gps_time = 1.0e5 + index * 1.0e-5;
    const bool modern = l.point_format >= 6;
    if (modern) {
        r[14] = std::byte{0x11}; // return 1 of 1
        r[16] = std::byte{p.classification};
        store_le<double>(r + 22, gps_time);
    } else {
        r[14] = std::byte{0x09}; // return 1 of 1
        r[15] = std::byte{p.classification};
        if (l.point_format != 0 && l.point_format != 2) store_le<double>(r + 20, gps_time);
    }
    const int rgb = lasmesh::rgb_offset(l.point_format);
    if (rgb >= 0) {
        for (int c = 0; c < 3; ++c) {
            std::uint16_t word = l.color_bits == 16 ? static_cast<std::uint16_t>(p.color[c] * 257) : p.color[c];
            store_le<std::uint16_t>(r + rgb + 2 * c, word);
        }
        if (l.point_format == 8 || l.point_format == 10) store_le<std::uint16_t>(r + rgb + 6, intensity); // NIR
    }
}

} // namespace lasgen
