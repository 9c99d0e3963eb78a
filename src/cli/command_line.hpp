// SPDX-License-Identifier: Apache-2.0
// The command line that repeats a run: what `lasmesh view` shows next to Save, to copy into a
// script. Only the options that differ from their defaults are written, each quoted for a POSIX
// shell where it needs it.
#pragma once

#include "mesh_command.hpp"

#include <string>

namespace lasmesh::cli {

// "lasmesh deck.las -o deck.ply --simplify 0.25cell": inputs, --inputs, outputs, then every option
// whose text differs from MeshOptions{}'s.
std::string command_line(const MeshOptions& options);

// `text` as one word for a POSIX shell: as it is when it holds only safe characters, else in
// single quotes.
std::string shell_word(const std::string& text);

} // namespace lasmesh::cli
