// SPDX-License-Identifier: Apache-2.0
// JSON for machine-readable output (the run report, the command line's JSON), through
// nlohmann-json. Internal: the library's public headers do not depend on a JSON library.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace lasmesh {

// Keys keep the order they were set in, so the output reads like the text summary.
using Json = nlohmann::ordered_json;

// One line, no spaces, ASCII only; non-finite numbers are null.
std::string json_line(const Json& json);

// One line, no spaces, UTF-8 as it is (glTF's JSON chunk); non-finite numbers are null.
std::string json_text(const Json& json);

// `text` when it is valid UTF-8, else its bytes read as Latin-1 (a file name in another encoding).
std::string utf8_or_latin1(std::string_view text);

// LAS strings are ASCII by the specification; any other byte a writer left in a field is taken
// as its Latin-1 code point, so the JSON stays valid whatever the file holds.
std::string latin1_to_utf8(std::string_view text);

// The shortest decimal text that reads back as the same double (text summaries).
std::string format_double(double number);

} // namespace lasmesh
