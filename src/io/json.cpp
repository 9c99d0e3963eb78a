// SPDX-License-Identifier: Apache-2.0
// JSON helpers: the dump settings and the two text conversions in one place.
#include "io/json.hpp"

#include <charconv>
#include <cstdint>

namespace lasmesh {

std::string json_line(const Json& json) {
    // ensure_ascii escapes every non-ASCII character; replace keeps invalid UTF-8 (a path in
    // another encoding) from throwing.
    return json.dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
}

std::string json_text(const Json& json) {
    return json.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

namespace {

// RFC 3629: no overlong forms, no surrogates, nothing past U+10FFFF.
bool valid_utf8(std::string_view text) {
    for (std::size_t i = 0; i < text.size();) {
        const auto c = static_cast<unsigned char>(text[i]);
        std::size_t n = 0;
        std::uint32_t code = 0;
        if (c < 0x80)
            n = 1, code = c;
        else if ((c & 0xE0) == 0xC0)
            n = 2, code = c & 0x1F;
        else if ((c & 0xF0) == 0xE0)
            n = 3, code = c & 0x0F;
        else if ((c & 0xF8) == 0xF0)
            n = 4, code = c & 0x07;
        else
            return false;
        if (i + n > text.size()) return false;
        for (std::size_t k = 1; k < n; ++k) {
            const auto d = static_cast<unsigned char>(text[i + k]);
            if ((d & 0xC0) != 0x80) return false;
            code = code << 6 | (d & 0x3F);
        }
        static constexpr std::uint32_t smallest[] = {0, 0, 0x80, 0x800, 0x10000};
        if (code < smallest[n] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return false;
        i += n;
    }
    return true;
}

} // namespace

std::string utf8_or_latin1(std::string_view text) {
    return valid_utf8(text) ? std::string(text) : latin1_to_utf8(text);
}

std::string latin1_to_utf8(std::string_view text) {
    std::string out;
    for (unsigned char c : text) {
        if (c < 0x80) {
            out += static_cast<char>(c);
        } else {
            out += static_cast<char>(0xC0 | (c >> 6));
            out += static_cast<char>(0x80 | (c & 0x3F));
        }
    }
    return out;
}

std::string format_double(double number) {
    char text[32];
    auto end = std::to_chars(text, text + sizeof text, number).ptr;
    return std::string(text, end);
}

} // namespace lasmesh
