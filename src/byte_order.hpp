// SPDX-License-Identifier: Apache-2.0
// Little-endian loads and stores for LAS fields, which may sit at any (unaligned) offset.
#pragma once

#include <bit>
#include <cstddef>
#include <cstring>

namespace lasmesh {

static_assert(std::endian::native == std::endian::little, "lasmesh reads little-endian LAS fields with plain copies");

template <typename T>
inline T load_le(const std::byte* at) {
    T value;
    std::memcpy(&value, at, sizeof(T));
    return value;
}

template <typename T>
inline void store_le(std::byte* at, T value) {
    std::memcpy(at, &value, sizeof(T));
}

} // namespace lasmesh
