// SPDX-License-Identifier: Apache-2.0
// Writing a mesh into an OutputFile that is not committed yet: build_mesh writes every output
// first and renames them all at the end.
#pragma once

#include "lasmesh/mesh.hpp"
#include "lasmesh/mesh_files.hpp"

#include <string>

namespace lasmesh {

class OutputFile;

// The format `output` asks for (its own, else its extension's); throws Error (usage, option
// "outputs") naming the path when the extension names none.
MeshFormat output_format(const OutputRequest& output);

// The bytes of `output` in `format` (its own or from its extension) into `file`; Error (output)
// messages start with the output's path. `facts_json` (a RunReport's JSON, or empty) goes into
// .html pages.
void write_mesh_into(const Mesh& mesh, const OutputRequest& output, MeshFormat format, const std::string& name,
                     OutputFile& file, const std::string& facts_json = {});

} // namespace lasmesh
