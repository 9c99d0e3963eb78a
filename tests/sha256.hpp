// SPDX-License-Identifier: Apache-2.0
// SHA-256 (FIPS 180-4) for the tests: the LAZ corpus lists the digest of all decoded records.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace test {

class Sha256 {
  public:
    Sha256();
    void add(std::span<const std::byte> bytes);
    std::string hex(); // finishes; lower-case hex digest

  private:
    void block(const std::uint8_t* p);
    std::array<std::uint32_t, 8> h_;
    std::array<std::uint8_t, 64> buffer_{};
    std::size_t buffered_ = 0;
    std::uint64_t total_ = 0;
};

} // namespace test
