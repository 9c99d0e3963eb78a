// JSON for the command line's machine-readable output (--json, --report), through nlohmann-json.
// Kept to src/cli: the library's public headers do not depend on a JSON library.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace lasmesh::cli {

// Keys keep the order they were set in, so the output reads like the text summary.
using Json = nlohmann::ordered_json;

// One line, no spaces, ASCII only; non-finite numbers are null.
std::string json_line(const Json& json);

// LAS strings are ASCII by the specification; any other byte a writer left in a field is taken
// as its Latin-1 code point, so the JSON stays valid whatever the file holds.
std::string latin1_to_utf8(std::string_view text);

// The shortest decimal text that reads back as the same double (text summaries).
std::string format_double(double number);

} // namespace lasmesh::cli
