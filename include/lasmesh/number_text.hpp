// SPDX-License-Identifier: Apache-2.0
// Numbers as the library's detail lines and the command line's summary print them, so both agree:
// shortest round trip, two significant digits for timings and steps, megabytes with one decimal.
#pragma once

#include <charconv>
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>

namespace lasmesh {

inline std::string shortest(double value) {
    char text[32];
    return std::string(text, std::to_chars(text, text + sizeof text, value).ptr);
}

// Four significant digits, for lengths and other measured values people read (0.1191, 977.5).
inline std::string four_digits(double value) {
    std::ostringstream text;
    text << std::setprecision(4) << value;
    return text.str();
}

inline std::string two_digits(double value) {
    std::ostringstream text;
    text << std::setprecision(2) << value;
    return text.str();
}

inline std::string megabytes(std::uint64_t bytes) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << bytes / 1e6 << " MB";
    return text.str();
}

// Binary megabytes, as --max-memory counts them.
inline std::string mebibytes(std::uint64_t bytes) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << bytes / 1048576.0 << " MiB";
    return text.str();
}

} // namespace lasmesh
