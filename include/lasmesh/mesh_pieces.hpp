// SPDX-License-Identifier: Apache-2.0
// Cleaning: removing the small isolated pieces of a mesh. Floating outlier clusters in a scan
// (spray, birds, stereo mismatches) are dense enough to pass any iso value, so they are told
// apart by what they are: small and disconnected from everything else.
#pragma once

#include "lasmesh/mesh.hpp"

#include <cstddef>
#include <string>

namespace lasmesh {

// A piece-size threshold: a fraction of the whole mesh's bounding-box diagonal, or a length in
// the file's units.
struct MinPiece {
    double value = 0.05;
    bool relative = true; // value is a fraction of the mesh diagonal
};

struct PieceCount {
    std::size_t pieces = 0;  // connected pieces before removal
    std::size_t removed = 0; // pieces removed
    std::size_t triangles_removed = 0;
    double min_diagonal = 0; // the threshold in file units
};

// Removes every connected piece (triangles linked through shared vertices, and pieces whose open
// borders come within a cell of each other: mesh.cell_size, when set) whose bounding-box
// diagonal is below the threshold, and the vertices only they used. The order of what stays
// is kept, so the result is as deterministic as the input.
PieceCount remove_small_pieces(Mesh& mesh, MinPiece min_piece);

} // namespace lasmesh
