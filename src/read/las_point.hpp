// SPDX-License-Identifier: Apache-2.0
// Decoding of raw point records: position through scale and offset, colour where the format
// has it. Inline, because it runs once per point.
#pragma once

#include "byte_order.hpp"
#include "read/las_header.hpp"

#include <array>
#include <cstdint>

namespace lasmesh {

using RawXYZ = std::array<std::int32_t, 3>;
using Rgb16 = std::array<std::uint16_t, 3>;

struct PointDecoder {
    std::size_t record_length = 0;
    Vec3 scale{};
    Vec3 offset{};
    int rgb_offset = -1; // -1: no colour

    explicit PointDecoder(const LasHeader& header)
        : record_length(header.point_record_length), scale(header.scale), offset(header.offset),
          rgb_offset(lasmesh::rgb_offset(header.point_format)) {}

    bool has_color() const { return rgb_offset >= 0; }

    // Every point format starts with X, Y, Z as 32-bit integers.
    static RawXYZ raw_xyz(const std::byte* record) {
        return {load_le<std::int32_t>(record), load_le<std::int32_t>(record + 4), load_le<std::int32_t>(record + 8)};
    }
    double to_world(int axis, std::int32_t raw) const { return raw * scale[axis] + offset[axis]; }
    Vec3 position(const std::byte* record) const {
        RawXYZ raw = raw_xyz(record);
        return {to_world(0, raw[0]), to_world(1, raw[1]), to_world(2, raw[2])};
    }
    // The stored 16-bit words; only valid when has_color().
    Rgb16 color(const std::byte* record) const {
        const std::byte* at = record + rgb_offset;
        return {load_le<std::uint16_t>(at), load_le<std::uint16_t>(at + 2), load_le<std::uint16_t>(at + 4)};
    }
};

} // namespace lasmesh
