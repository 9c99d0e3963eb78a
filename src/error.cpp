// SPDX-License-Identifier: Apache-2.0
// Error: a message plus the kind that selects the exit code.
#include "lasmesh/error.hpp"

#include <utility>

namespace lasmesh {

Error::Error(ErrorKind kind, const std::string& message, std::string option, std::string suggestion)
    : std::runtime_error(message), kind_(kind), option_(std::move(option)), suggestion_(std::move(suggestion)) {}

void throw_input_error(const std::string& source, const std::string& what, std::string option) {
    throw Error(ErrorKind::input, source + ": " + what, std::move(option));
}

} // namespace lasmesh
