// SPDX-License-Identifier: Apache-2.0
// The sRGB transfer functions of IEC 61966-2-1: a linear toe below 0.04045 (0.0031308 linear),
// a 2.4 power curve above.
#include "io/srgb.hpp"

#include <algorithm>
#include <cmath>

namespace lasmesh {

std::uint16_t srgb8_to_linear16(std::uint8_t value) {
    const double s = value / 255.0;
    const double linear = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
    return static_cast<std::uint16_t>(std::lround(linear * 65535.0));
}

std::uint8_t linear16_to_srgb8(std::uint16_t value) {
    const double l = value / 65535.0;
    const double s = l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
    return static_cast<std::uint8_t>(std::lround(std::clamp(s, 0.0, 1.0) * 255.0));
}

} // namespace lasmesh
