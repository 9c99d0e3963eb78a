// SPDX-License-Identifier: Apache-2.0
// The public header block of an ASPRS LAS 1.0-1.4 file (R15), its VLR list, and the facts of
// point data record formats 0-10. Written from the specification.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lasmesh {

class InputStream;

using Vec3 = std::array<double, 3>;

// A variable length record as listed in the header area; its payload is read past, not kept
// (except the LASzip VLR's, which the LAZ decoder needs).
struct Vlr {
    std::string user_id; // up to 16 characters, trailing NULs removed
    std::uint16_t record_id = 0;
    std::uint16_t length = 0;    // payload bytes after the 54-byte VLR header
    std::string description;     // up to 32 characters, trailing NULs removed
    std::vector<std::byte> data; // the payload, kept only for the LASzip VLR
};

struct LasHeader {
    std::uint8_t version_major = 1;
    std::uint8_t version_minor = 2;
    std::uint16_t global_encoding = 0;
    std::string system_identifier;
    std::string generating_software;
    std::uint16_t header_size = 0;
    std::uint32_t offset_to_point_data = 0;
    std::uint32_t vlr_count = 0;
    std::uint8_t point_format = 0; // 0-10, with the LAZ compression bits 6 and 7 cleared
    bool compressed = false;       // LAZ: a LASzip VLR (and the compression bit)
    std::uint16_t point_record_length = 0;
    std::uint32_t legacy_point_count = 0;
    // The number of records to read: the 64-bit count for LAS 1.4, the legacy count before.
    std::uint64_t point_count = 0;
    Vec3 scale{};
    Vec3 offset{};
    Vec3 min{};
    Vec3 max{};
    std::vector<Vlr> vlrs;
    // Where data the format puts after the point records starts (LAS 1.3 waveform packets, LAS
    // 1.4 extended VLRs); 0 when none: then any bytes after the last record are unexpected.
    std::uint64_t start_after_points = 0;
};

// Size of the record fields a point format defines, before any extra bytes.
std::uint16_t core_record_size(int point_format);
// Byte offset of the red, green, blue words in a record, or -1 when the format has no colour.
int rgb_offset(int point_format);
// Smallest header the version defines: 227 bytes for 1.0-1.2, 235 for 1.3, 375 for 1.4.
std::uint16_t minimum_header_size(int version_minor);

inline bool has_color(const LasHeader& header) {
    return rgb_offset(header.point_format) >= 0;
}
std::string version_string(const LasHeader& header);

// Reads the header block and the VLRs, then reads past any gap up to the offset to point data,
// so the stream is left at the first point record. Validates as it goes and throws Error (input)
// naming the stream, the byte offset and what was expected: bad signature, unsupported version,
// inconsistent sizes or offsets, bad scale factors, VLRs that overrun the point data.
LasHeader read_las_header(InputStream& in);

// Header bounds are used as the grid's box: throws Error (input), naming the header field, when
// an axis's bounds lie beyond every coordinate a record can encode (offset + scale * int32) or
// span more than float positions can hold. `name` is the input's, for the message.
void check_header_bounds_usable(const LasHeader& header, const std::string& name);

} // namespace lasmesh
