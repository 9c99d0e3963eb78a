// A minimal JSON writer for the command line's machine-readable output (one line, no spaces).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace lasmesh::cli {

class JsonWriter {
public:
    JsonWriter& begin_object();
    JsonWriter& end_object();
    JsonWriter& begin_array();
    JsonWriter& end_array();
    JsonWriter& key(std::string_view name);
    JsonWriter& value(std::string_view text);
    JsonWriter& value(const char* text) { return value(std::string_view(text)); }
    JsonWriter& value(double number); // shortest round-trip form; null when not finite
    JsonWriter& value(std::uint64_t number);
    JsonWriter& value(bool flag);
    template <typename Array>
    JsonWriter& array(const Array& values) {
        begin_array();
        for (const auto& v : values) {
            if constexpr (std::is_integral_v<std::decay_t<decltype(v)>>)
                value(static_cast<std::uint64_t>(v));
            else
                value(v);
        }
        return end_array();
    }
    const std::string& str() const { return out_; }

private:
    void separate();
    std::string out_;
    std::vector<bool> has_items_; // per open container: whether a comma is due
    bool after_key_ = false;
};

// The shortest decimal text that reads back as the same double.
std::string format_double(double number);

} // namespace lasmesh::cli
