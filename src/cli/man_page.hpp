// SPDX-License-Identifier: Apache-2.0
// The man page, written from the same CLI11 declarations as --help (names, values, defaults,
// descriptions, each command's examples), so the two cannot disagree. `lasmesh --man` prints
// it; the build writes build/lasmesh.1 from it and installs that.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace lasmesh::cli {

std::string man_page(const CLI::App& app, const std::string& version);

} // namespace lasmesh::cli
