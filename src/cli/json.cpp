// JSON helpers: the dump settings and the two text conversions in one place.
#include "json.hpp"

#include <charconv>

namespace lasmesh::cli {

std::string json_line(const Json& json) {
    // ensure_ascii escapes every non-ASCII character; replace keeps invalid UTF-8 (a path in
    // another encoding) from throwing.
    return json.dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
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

} // namespace lasmesh::cli
