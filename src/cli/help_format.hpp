// SPDX-License-Identifier: Apache-2.0
// How an option reads in --help and in the man page, from the one declaration both are written
// from: its names, the value it takes as declared with type_name ("sheet|closed", "N|auto"), its
// description and its default. CLI11's own notes (TEXT, UINT:1-17179869184, Excludes:) stay out.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace lasmesh::cli {

// "sheet|closed", "FILE", "N|NXxNYxNZ|auto"; empty for a flag and for a positional.
std::string value_text(const CLI::Option& option);

// The description, then " (default: X)" when the option has a default to show.
std::string description_text(const CLI::Option& option);

// CLI11's formatter with the two above for each option's value and description.
class HelpFormatter : public CLI::Formatter {
  public:
    std::string make_option_opts(const CLI::Option* option) const override;
    std::string make_option_desc(const CLI::Option* option) const override;
};

} // namespace lasmesh::cli
