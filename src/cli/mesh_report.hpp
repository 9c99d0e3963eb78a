// SPDX-License-Identifier: Apache-2.0
// How the meshing command presents a run: the text summary for people (the --report JSON for
// pipelines is the library's: run_report_json). It reads the library's RunReport.
#pragma once

#include "lasmesh/build_mesh.hpp"

#include <ostream>
#include <string>

namespace lasmesh::cli {

// What the summary needs beyond the report: the options as the user spelled them.
struct SummaryContext {
    std::string min_piece_text; // "5%": quoted when the threshold is relative
    bool relative_min_piece = true;
    std::string simplify_text;  // "0.5cell"
    const Mesh* mesh = nullptr; // for the Draco line: bits and step depend on the mesh
    DracoOptions draco;
    bool any_draco = false;
};

void print_summary(const RunReport& report, const SummaryContext& context, std::ostream& out);

} // namespace lasmesh::cli
