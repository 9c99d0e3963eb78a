// SPDX-License-Identifier: Apache-2.0
// Vertices found by their place, bit for bit: tiles meshed apart give the vertices they share
// the same bits, so joining them needs no tolerance.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <unordered_map>

namespace lasmesh {

struct PlaceBits {
    std::size_t operator()(const std::array<float, 3>& p) const {
        std::uint64_t h = 0;
        for (const float c : p) h = (h ^ std::bit_cast<std::uint32_t>(c)) * 0x100000001b3ull;
        return static_cast<std::size_t>(h);
    }
};
struct SameBits {
    bool operator()(const std::array<float, 3>& a, const std::array<float, 3>& b) const {
        for (int k = 0; k < 3; ++k)
            if (std::bit_cast<std::uint32_t>(a[k]) != std::bit_cast<std::uint32_t>(b[k])) return false;
        return true;
    }
};
template <class Value>
using PlaceMap = std::unordered_map<std::array<float, 3>, Value, PlaceBits, SameBits>;

} // namespace lasmesh
