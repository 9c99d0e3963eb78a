// SPDX-License-Identifier: Apache-2.0
// COPC (cloud-optimised point cloud, COPC 1.0 specification): a LAZ 1.4 file whose chunks are
// the nodes of an octree. Its info VLR gives the root cube (centre and half its edge) and where
// the hierarchy is: pages of 32-byte entries, each a node's key (level, x, y, z), the offset and
// size of its chunk, and its point count (-1: the entry points at another page). A node's points
// lie in its cube, so a reader that wants a region reads only the chunks whose cubes meet it.
#pragma once

#include "lasmesh/grid.hpp"
#include "lasmesh/las_reader.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lasmesh {

struct CopcNode {
    std::array<std::int32_t, 4> key{}; // level, x, y, z
    std::uint64_t offset = 0;          // the chunk's first byte in the file
    std::uint64_t bytes = 0;
    std::uint64_t points = 0;
    Bounds cube; // in the file's coordinates
};

// The nodes holding points, in file order (by offset); nullopt when `header` has no COPC info
// VLR. Read from the file at `path` (the hierarchy is at its end). Throws Error (input) naming
// the file and the page when the hierarchy is damaged: a page outside the file, a page read twice,
// nodes that overlap or fall outside the point data, or points that do not add up to the
// header's count.
std::optional<std::vector<CopcNode>> read_copc_nodes(const std::string& path, const LasHeader& header);

} // namespace lasmesh
