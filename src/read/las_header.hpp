// SPDX-License-Identifier: Apache-2.0
// Reading and checking the public header block of an ASPRS LAS 1.0-1.4 file (R15) and its VLRs,
// and the facts of point data record formats 0-10. Written from the specification.
#pragma once

#include "lasmesh/las_reader.hpp"
#include "lasmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lasmesh {

class InputStream;

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

// The coordinate system's extended VLRs (LASF_Projection, LAS 1.4) of the file at `path`, into
// header.crs_evlrs: a handle of its own seeks to them. EVLRs that do not fit in the file are
// left out (they describe, they hold no points); payloads over 1 MiB are not kept.
void read_crs_evlrs(const std::string& path, LasHeader& header);

// Header bounds are used as the grid's box: throws Error (input), naming the header field, when
// an axis's bounds lie beyond every coordinate a record can encode (offset + scale * int32) or
// span more than float positions can hold. `name` is the input's, for the message.
void check_header_bounds_usable(const LasHeader& header, const std::string& name);

} // namespace lasmesh
