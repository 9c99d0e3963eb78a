// SPDX-License-Identifier: Apache-2.0
// Internal: what the pointwise GPSTIME11 (v2) and the layered POINT14 (v3/v4) decoders share for
// GPS times. A time's difference from the last is predicted as a multiple of the last difference;
// the decoded multiplier says which (0..500 times, 501..510 for -1..-10 times), and picks the
// integer decoder's context. Both formats code the other symbols (unchanged, a full new time, a
// switch to another of four sequences) differently, so those stay in their decoders.
#pragma once

#include <cstdint>

namespace lasmesh::laz {

constexpr std::int32_t gps_multi = 500;       // the largest multiplier
constexpr std::int32_t gps_multi_minus = -10; // the most negative one

// Wrapping arithmetic: corrupt input must not overflow a signed type.
inline std::int32_t add32(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b));
}
inline std::int64_t add64(std::int64_t a, std::int64_t b) {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) + static_cast<std::uint64_t>(b));
}
inline std::int32_t mul32(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) * static_cast<std::uint32_t>(b));
}

struct GpsTimePrediction {
    std::int32_t difference; // the predicted difference from the last time
    std::uint32_t context;   // the integer decoder's context for the correction
    bool extreme;            // an extreme multiplier: a run of them replaces the last difference
};

// For a multiplier symbol below 511 (the caller checks), with context per kind of multiplier.
inline GpsTimePrediction predict_gps_difference(std::int32_t multi, std::int32_t last_diff) {
    if (multi == 0) return {0, 7, true};
    if (multi == 1) return {last_diff, 1, false};
    if (multi < gps_multi) return {mul32(multi, last_diff), multi < 10 ? 2u : 3u, false};
    if (multi == gps_multi) return {mul32(gps_multi, last_diff), 4, true};
    const std::int32_t negative = gps_multi - multi; // -1 .. -10
    if (negative > gps_multi_minus) return {mul32(negative, last_diff), 5, false};
    return {mul32(gps_multi_minus, last_diff), 6, true};
}

} // namespace lasmesh::laz
