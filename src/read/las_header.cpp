// SPDX-License-Identifier: Apache-2.0
// Parsing and validation of the LAS public header block and VLRs (LAS 1.4 R15, section 2).
#include "read/las_header.hpp"
#include "number_text.hpp"

#include "byte_order.hpp"
#include "lasmesh/error.hpp"
#include "read/input_stream.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <vector>

namespace lasmesh {

std::uint16_t core_record_size(int point_format) {
    static constexpr std::uint16_t sizes[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
    return point_format >= 0 && point_format <= 10 ? sizes[point_format] : 0;
}

int rgb_offset(int point_format) {
    switch (point_format) {
    case 2: return 20; // after the 20-byte core of format 0
    case 3:
    case 5: return 28; // after format 1's GPS time
    case 7:
    case 8:
    case 10: return 30; // after format 6's 30-byte core
    default: return -1;
    }
}

std::uint16_t minimum_header_size(int version_minor) {
    return version_minor >= 4 ? 375 : version_minor == 3 ? 235 : 227;
}

std::string version_string(const LasHeader& header) {
    return std::to_string(header.version_major) + "." + std::to_string(header.version_minor);
}

namespace {

constexpr std::size_t vlr_header_size = 54;
// The LASzip VLR marks a LAZ file even when a writer left the point format bits clear.
constexpr const char* laszip_user_id = "laszip encoded";
constexpr std::uint16_t laszip_record_id = 22204;

std::string fixed_string(const std::byte* at, std::size_t size) {
    std::string text(reinterpret_cast<const char*>(at), size);
    text.resize(text.find('\0') == std::string::npos ? size : text.find('\0'));
    return text;
}

std::string hex_byte(unsigned value) {
    char text[8];
    std::snprintf(text, sizeof text, "0x%02X", value & 0xFFu);
    return text;
}

std::string printable(const std::byte* at, std::size_t size) {
    std::string text;
    for (std::size_t i = 0; i < size; ++i) {
        unsigned c = std::to_integer<unsigned>(at[i]);
        text += (c >= 0x20 && c < 0x7F) ? std::string(1, static_cast<char>(c)) : "\\x" + hex_byte(c).substr(2);
    }
    return text;
}

// Reads exactly `size` bytes or throws, naming what was being read.
void read_exactly(InputStream& in, std::byte* dst, std::size_t size, const std::string& what) {
    std::uint64_t at = in.position();
    std::size_t got = in.read(dst, size);
    if (got < size) {
        // A compressed stream that yields nothing is a damaged one, not an empty file: Boost's zstd
        // filter, for one, ends quietly where a frame is cut short.
        if (at == 0 && got == 0 && in.compression() != Compression::none)
            throw_input_error(in.name(), "corrupt or truncated " + std::string(compression_name(in.compression())) +
                                             " stream near compressed byte " + std::to_string(in.raw_position()) +
                                             ": it decompresses to nothing");
        if (at == 0 && got == 0) throw_input_error(in.name(), "is empty, expected a LAS file");
        throw_input_error(in.name(), "ends at byte " + std::to_string(at + got) + " inside " + what + " (bytes " +
                                         std::to_string(at) + " to " + std::to_string(at + size) + ")");
    }
}

Vec3 load_vec3(const std::byte* at) {
    return {load_le<double>(at), load_le<double>(at + 8), load_le<double>(at + 16)};
}

void validate_vec3(const InputStream& in, const Vec3& v, std::size_t field_offset, const char* field, bool nonzero) {
    // Scale and offset are three doubles each, X first.
    static const char* axis = "XYZ";
    for (int i = 0; i < 3; ++i) {
        std::string where = std::string(1, axis[i]) + " " + field + " at byte " + std::to_string(field_offset + 8 * i);
        if (!std::isfinite(v[i])) throw_input_error(in.name(), where + " is not a finite number");
        if (nonzero && v[i] == 0.0) throw_input_error(in.name(), where + " is zero");
        // Positive scales keep raw integers and coordinates in the same order, which the grid's
        // integer cell boundaries rely on; no writer we know of uses negative ones.
        if (nonzero && v[i] < 0.0) throw_input_error(in.name(), where + " is negative");
    }
}

} // namespace

LasHeader read_las_header(InputStream& in) {
    LasHeader h;
    std::vector<std::byte> block(227);
    read_exactly(in, block.data(), 4, "the file signature");
    if (fixed_string(block.data(), 4) != "LASF" || block[3] != std::byte{'F'})
        throw_input_error(in.name(), "is not a LAS file: expected the signature \"LASF\" at byte 0, found \"" +
                                         printable(block.data(), 4) + "\"");
    read_exactly(in, block.data() + 4, 227 - 4, "the LAS header");
    const std::byte* b = block.data();

    h.version_major = std::to_integer<std::uint8_t>(b[24]);
    h.version_minor = std::to_integer<std::uint8_t>(b[25]);
    if (h.version_major != 1 || h.version_minor > 4)
        throw_input_error(in.name(),
                          "has LAS version " + version_string(h) + " (bytes 24-25); lasmesh reads LAS 1.0 to 1.4");
    h.global_encoding = h.version_minor >= 2 ? load_le<std::uint16_t>(b + 6) : 0;
    h.system_identifier = fixed_string(b + 26, 32);
    h.generating_software = fixed_string(b + 58, 32);
    h.header_size = load_le<std::uint16_t>(b + 94);
    h.offset_to_point_data = load_le<std::uint32_t>(b + 96);
    h.vlr_count = load_le<std::uint32_t>(b + 100);
    unsigned format_byte = std::to_integer<unsigned>(b[104]);
    h.point_record_length = load_le<std::uint16_t>(b + 105);
    h.legacy_point_count = load_le<std::uint32_t>(b + 107);
    h.point_count = h.legacy_point_count;
    h.scale = load_vec3(b + 131);
    h.offset = load_vec3(b + 155);
    // The header stores max before min for each axis.
    h.max = {load_le<double>(b + 179), load_le<double>(b + 195), load_le<double>(b + 211)};
    h.min = {load_le<double>(b + 187), load_le<double>(b + 203), load_le<double>(b + 219)};

    std::uint16_t minimum = minimum_header_size(h.version_minor);
    if (h.header_size < minimum)
        throw_input_error(in.name(), "header size " + std::to_string(h.header_size) +
                                         " (byte 94) is smaller than the " + std::to_string(minimum) + " bytes LAS " +
                                         version_string(h) + " defines");
    if (h.offset_to_point_data < h.header_size)
        throw_input_error(in.name(), "offset to point data " + std::to_string(h.offset_to_point_data) +
                                         " (byte 96) lies inside the " + std::to_string(h.header_size) +
                                         "-byte header");
    block.resize(h.header_size);
    b = block.data();
    read_exactly(in, block.data() + 227, h.header_size - 227u, "the LAS header");
    if (h.version_minor >= 4) h.point_count = load_le<std::uint64_t>(b + 247);
    // LAS 1.4 keeps the legacy count 0 (formats 6-10, or past 2^32) or equal to the 64-bit one:
    // a legacy count that the 64-bit count contradicts leaves no count to trust.
    if (h.version_minor >= 4 && h.legacy_point_count != 0 && h.legacy_point_count != h.point_count)
        throw_input_error(in.name(), "its 64-bit point count (bytes 247-254) is " + std::to_string(h.point_count) +
                                         " but its legacy point count (bytes 107-110) is " +
                                         std::to_string(h.legacy_point_count) +
                                         ": the header is inconsistent; rewrite it, e.g. with `las2las`");
    if (h.version_minor >= 3) h.start_after_points = load_le<std::uint64_t>(b + 227); // waveform data
    if (h.version_minor >= 4 && h.start_after_points == 0) h.start_after_points = load_le<std::uint64_t>(b + 235);
    if (h.version_minor >= 4) {
        h.evlr_start = load_le<std::uint64_t>(b + 235);
        h.evlr_count = load_le<std::uint32_t>(b + 243);
    }

    // LAZ (LASzip): bit 7 (and bit 6 from early writers) marks compressed points; the record
    // length stays that of the uncompressed record.
    const bool compression_bits = (format_byte & 0xC0u) != 0;
    h.point_format = static_cast<std::uint8_t>(format_byte & 0x3Fu);
    if (h.point_format > 10)
        throw_input_error(in.name(), "point data format " + std::to_string(h.point_format) +
                                         " (byte 104) is not one of the LAS formats 0 to 10");
    if (h.point_record_length < core_record_size(h.point_format))
        throw_input_error(in.name(), "point record length " + std::to_string(h.point_record_length) +
                                         " (byte 105) is shorter than the " +
                                         std::to_string(core_record_size(h.point_format)) + " bytes point format " +
                                         std::to_string(h.point_format) + " needs");
    validate_vec3(in, h.scale, 131, "scale factor", true);
    validate_vec3(in, h.offset, 155, "offset", false);
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(h.min[i]) || !std::isfinite(h.max[i]))
            throw_input_error(in.name(), "header bounds (bytes 179-226) are not finite numbers");
    if (h.point_count > 0)
        for (int i = 0; i < 3; ++i)
            if (h.min[i] > h.max[i])
                throw_input_error(
                    in.name(), std::string("header bounds are inverted: min ") + "XYZ"[i] + " " + shortest(h.min[i]) +
                                   " > max " + shortest(h.max[i]) +
                                   " (bytes 179-226): the header is damaged; rewrite its bounds from the points, e.g. "
                                   "with `lasinfo -repair_bb`");

    // VLRs sit between the header and the point data; one that runs past the offset to point
    // data means the count or a length is wrong, and its "payload" would be point records.
    for (std::uint32_t i = 0; i < h.vlr_count; ++i) {
        std::uint64_t at = in.position();
        if (at + vlr_header_size > h.offset_to_point_data)
            throw_input_error(
                in.name(), "VLR " + std::to_string(i) + " of " + std::to_string(h.vlr_count) + " would start at byte " +
                               std::to_string(at) + " and run past the offset to point data " +
                               std::to_string(h.offset_to_point_data) + ": the header's VLR count (byte 100) is wrong");
        std::array<std::byte, vlr_header_size> raw;
        read_exactly(in, raw.data(), raw.size(), "VLR " + std::to_string(i));
        Vlr vlr;
        vlr.user_id = fixed_string(raw.data() + 2, 16);
        vlr.record_id = load_le<std::uint16_t>(raw.data() + 18);
        vlr.length = load_le<std::uint16_t>(raw.data() + 20);
        vlr.description = fixed_string(raw.data() + 22, 32);
        std::uint64_t end = at + vlr_header_size + vlr.length;
        if (end > h.offset_to_point_data)
            throw_input_error(
                in.name(), "VLR " + std::to_string(i) + " (user id \"" + printable(raw.data() + 2, vlr.user_id.size()) +
                               "\", record " + std::to_string(vlr.record_id) + ", " + std::to_string(vlr.length) +
                               " bytes at byte " + std::to_string(at + vlr_header_size) +
                               ") runs past the offset to point data " + std::to_string(h.offset_to_point_data));
        const bool laszip = vlr.user_id == laszip_user_id && vlr.record_id == laszip_record_id;
        // The coordinate system (read_crs): the WKT and the GeoTIFF keys, doubles and text.
        const bool projection = vlr.user_id == "LASF_Projection" &&
                                (vlr.record_id == 2112 || (vlr.record_id >= 34735 && vlr.record_id <= 34737));
        // COPC's info record: where its octree's hierarchy is (read/copc.hpp).
        const bool copc = vlr.user_id == "copc" && vlr.record_id == 1;
        if (laszip || projection || copc) {
            vlr.data.resize(vlr.length);
            if (in.read(vlr.data.data(), vlr.length) < vlr.length)
                throw_input_error(in.name(),
                                  "ends inside VLR " + std::to_string(i) + " at byte " + std::to_string(in.position()));
            h.compressed = h.compressed || laszip;
        } else if (in.skip(vlr.length) < vlr.length)
            throw_input_error(in.name(),
                              "ends inside VLR " + std::to_string(i) + " at byte " + std::to_string(in.position()));
        h.vlrs.push_back(std::move(vlr));
    }

    if (compression_bits && !h.compressed)
        throw_input_error(in.name(), "point format byte " + hex_byte(format_byte) +
                                         " at byte 104 has the LAZ compression bits set, but there is no LASzip VLR "
                                         "(user id \"laszip encoded\", record 22204) to say how");

    // Some writers leave a gap (LAS 1.0's 0xDDCC start signature, padding) before the points.
    std::uint64_t gap = h.offset_to_point_data - in.position();
    if (in.skip(gap) < gap)
        throw_input_error(in.name(), "ends at byte " + std::to_string(in.position()) +
                                         ", before the offset to point data " + std::to_string(h.offset_to_point_data));
    return h;
}

void check_header_bounds_usable(const LasHeader& h, const std::string& name) {
    auto text = shortest;
    for (int a = 0; a < 3; ++a) {
        const std::string field = std::string("header bounds min/max ") + "XYZ"[a] + " (bytes " +
                                  std::to_string(179 + 16 * a) + "-" + std::to_string(194 + 16 * a) + ": " +
                                  text(h.min[a]) + " to " + text(h.max[a]) + ")";
        // One step of slack each way: writers round the bounds outwards.
        const double lowest = h.offset[a] + (std::numeric_limits<std::int32_t>::min() - 1.0) * h.scale[a];
        const double highest = h.offset[a] + (std::numeric_limits<std::int32_t>::max() + 1.0) * h.scale[a];
        if (h.min[a] < lowest || h.max[a] > highest)
            throw_input_error(name,
                              field + " lie beyond every coordinate a record can hold (" + text(lowest) + " to " +
                                  text(highest) +
                                  " with this scale and offset): the header is damaged; "
                                  "scan the points for their bounds, or give bounds",
                              "scan_bounds,bounds");
        if (!(h.max[a] - h.min[a] < 1e37))
            throw_input_error(name,
                              field + " span more than a mesh's float positions can hold: the header is "
                                      "damaged; scan the points for their bounds, or give bounds",
                              "scan_bounds,bounds");
    }
}

void read_crs_evlrs(const std::string& path, LasHeader& header) {
    constexpr std::uint64_t evlr_header = 60, largest_kept = std::uint64_t{1} << 20;
    if (header.evlr_count == 0 || header.evlr_start == 0) return;
    std::ifstream file(path, std::ios::binary);
    file.seekg(0, std::ios::end);
    const auto size = static_cast<std::uint64_t>(std::max<std::streamoff>(file.tellg(), 0));
    std::uint64_t at = header.evlr_start;
    for (std::uint32_t i = 0; i < header.evlr_count && file && at <= size && size - at >= evlr_header; ++i) {
        std::array<std::byte, evlr_header> head{};
        file.seekg(static_cast<std::streamoff>(at));
        if (!file.read(reinterpret_cast<char*>(head.data()), evlr_header)) return;
        const std::uint64_t length = load_le<std::uint64_t>(head.data() + 20);
        if (length > size - at - evlr_header) return;
        Vlr vlr;
        vlr.user_id = fixed_string(head.data() + 2, 16);
        vlr.record_id = load_le<std::uint16_t>(head.data() + 18);
        vlr.length = static_cast<std::uint16_t>(std::min<std::uint64_t>(length, 65535));
        vlr.description = fixed_string(head.data() + 28, 32);
        if (vlr.user_id == "LASF_Projection" && length <= largest_kept) {
            vlr.data.resize(length);
            if (!file.read(reinterpret_cast<char*>(vlr.data.data()), static_cast<std::streamsize>(length))) return;
            header.crs_evlrs.push_back(std::move(vlr));
        }
        at += evlr_header + length;
    }
}

} // namespace lasmesh
