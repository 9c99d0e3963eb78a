// SPDX-License-Identifier: Apache-2.0
// Errors that reach the user: one exception type whose kind decides the process exit code.
#pragma once

#include <stdexcept>
#include <string>

namespace lasmesh {

// Exit codes of the `lasmesh` command (documented in docs/usage.md); 0 is success.
enum class ErrorKind {
    usage = 1,  // bad command line
    input = 2,  // unreadable or malformed input
    device = 3, // OpenCL platform, device or kernel problem
    output = 4, // output cannot be written
};

// Thrown for every failure a user can act on. The message is one line that names the file,
// the byte offset or record where known, what was expected and what was found.
class Error : public std::runtime_error {
  public:
    // `option`: the field of BuildOptions the error is about ("grid", "outputs"; several with
    // commas: "scan_bounds,bounds"), so that a front end can name its own spelling of it (the
    // command line's flag); empty when none is. `suggestion`: a value of that option that would
    // work ("512" for a grid that fits), or empty. The message itself says it in words.
    Error(ErrorKind kind, const std::string& message, std::string option = {}, std::string suggestion = {});
    ErrorKind kind() const noexcept { return kind_; }
    int exit_code() const noexcept { return static_cast<int>(kind_); }
    const std::string& option() const noexcept { return option_; }
    const std::string& suggestion() const noexcept { return suggestion_; }

  private:
    ErrorKind kind_;
    std::string option_, suggestion_;
};

// Shorthand for the most common kind: a problem with an input named `source`.
[[noreturn]] void throw_input_error(const std::string& source, const std::string& what, std::string option = {});

} // namespace lasmesh
