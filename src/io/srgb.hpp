// SPDX-License-Identifier: Apache-2.0
// sRGB <-> linear colour. LAS colours are sRGB-encoded, glTF vertex colours (COLOR_0) are linear:
// the .glb stores linear values as 16-bit words, fine enough that every 8-bit sRGB value comes
// back exactly.
#pragma once

#include <cstdint>

namespace lasmesh {

// The sRGB decoding function (IEC 61966-2-1) of `value / 255`, as a 16-bit word (65535 is 1.0).
std::uint16_t srgb8_to_linear16(std::uint8_t value);

// The inverse: the nearest 8-bit sRGB value of a linear 16-bit word.
std::uint8_t linear16_to_srgb8(std::uint16_t value);

} // namespace lasmesh
