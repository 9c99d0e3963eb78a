// SPDX-License-Identifier: Apache-2.0
// The option text --help and the man page share.
#include "help_format.hpp"

namespace lasmesh::cli {

std::string value_text(const CLI::Option& option) {
    if (option.get_items_expected_max() == 0 || option.get_positional()) return "";
    const std::string type = option.get_type_name(); // the declared name, then ":" and validators' notes
    return type.substr(0, type.find(':'));
}

std::string description_text(const CLI::Option& option) {
    std::string text = option.get_description();
    if (!option.get_default_str().empty() && option.get_items_expected_max() > 0)
        text += " (default: " + option.get_default_str() + ")";
    return text;
}

std::string HelpFormatter::make_option_opts(const CLI::Option* option) const {
    const std::string value = value_text(*option);
    return value.empty() ? "" : " " + value;
}

std::string HelpFormatter::make_option_desc(const CLI::Option* option) const {
    return description_text(*option);
}

} // namespace lasmesh::cli
