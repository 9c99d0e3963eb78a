// SPDX-License-Identifier: Apache-2.0
// `lasmesh info`: the header facts of a LAS input, optionally checked against a full scan.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace lasmesh::cli {

struct InfoOptions {
    std::vector<std::string> inputs;
    bool json = false;
    bool scan = false;
    std::size_t chunk_points = 1 << 16;
};

// Writes the report to `out`; throws lasmesh::Error on bad input.
// Warnings (records beyond the header's count, found by --scan) go to `log`.
void run_info(const InfoOptions& options, std::ostream& out, std::ostream& log);

} // namespace lasmesh::cli
