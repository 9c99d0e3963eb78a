// SPDX-License-Identifier: Apache-2.0
// Numbers as the library's detail lines and the command line's summary print them, so both agree:
// shortest round trip, two significant digits for timings and steps, megabytes with one decimal.
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <string>

namespace lasmesh {

inline std::string shortest(double value) {
    char text[32];
    return std::string(text, std::to_chars(text, text + sizeof text, value).ptr);
}

// `digits` significant digits, without an exponent where a person reads better without one
// (0.1191, 977.5, 2360, 797000); very large or small values keep it (1e+300).
inline std::string significant(double value, int digits) {
    std::ostringstream text;
    const double magnitude = std::abs(value);
    if (magnitude >= 1e-4 && magnitude < 1e12) {
        const int exponent = static_cast<int>(std::floor(std::log10(magnitude)));
        const int decimals = std::max(0, digits - 1 - exponent);
        // Past the point's left, round to the digits too: 796931 to 797000.
        const double unit = decimals == 0 ? std::pow(10.0, exponent - digits + 1) : 1;
        text << std::fixed << std::setprecision(decimals) << (unit > 1 ? std::round(value / unit) * unit : value);
        std::string t = text.str();
        // No trailing zeros after the point: 0.5, not 0.5000.
        if (t.find('.') != std::string::npos) {
            t.erase(t.find_last_not_of('0') + 1);
            if (t.back() == '.') t.pop_back();
        }
        return t;
    }
    text << std::setprecision(digits) << value;
    return text.str();
}

// A coordinate to the decimals that resolve `step` (at least one): a grid's origin to a
// thousandth of its cell (431249.9043 for cells of 0.12), where all 17 digits would only hide it.
inline std::string coordinate(double value, double step) {
    const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(step))), 1, 12);
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

// Four significant digits, for lengths and other measured values people read (0.1191, 977.5).
inline std::string four_digits(double value) {
    return significant(value, 4);
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

// Binary megabytes, as the memory limit counts them.
inline std::string mebibytes(std::uint64_t bytes) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << bytes / 1048576.0 << " MiB";
    return text.str();
}

} // namespace lasmesh
