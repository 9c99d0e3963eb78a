// SPDX-License-Identifier: Apache-2.0
// The LAZ chunk table (LASzip format description, "chunk table"): written after the last
// chunk, pointed at by the 64-bit offset that precedes the first chunk. It lists each chunk's
// compressed size (and, for variable-size chunks, its point count), coded with the integer
// decoder, each value predicted by the previous chunk's.
#pragma once

#include "read/laz_vlr.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace lasmesh::laz {

struct Chunk {
    std::uint64_t points = 0;
    std::uint64_t offset = 0; // file offset of the chunk's first byte
    std::uint64_t bytes = 0;
};

// Decodes the table from `table` (the bytes from the table offset on: u32 version, u32 chunk
// count, coded sizes) and places the chunks from `first_chunk_offset`. Checks that the chunks
// end at or before `table_offset` and that they hold at least `point_count` points; throws Error
// (input) naming `source` otherwise. Chunks past the header's count are left out of the result
// and said in `beyond` ("2 more chunks", "10000 more points"; empty when none).
std::vector<Chunk> decode_chunk_table(std::span<const std::byte> table, const Format& format, std::uint64_t point_count,
                                      std::uint64_t first_chunk_offset, std::uint64_t table_offset,
                                      const std::string& source, std::string& beyond);

// Every point costs a few adaptive-symbol decodes, at least a few thousandths of a bit each, so
// a chunk of `bytes` compressed bytes holds well under 2048 points per byte (about 1000 for
// identical format-0 points, the cheapest case).
// Checked before records are allocated, so a corrupt count cannot ask for terabytes.
inline bool plausible_points(std::uint64_t points, std::uint64_t bytes) {
    return points <= bytes * 2048 + 1;
}

// Layered chunks (compressor 3) describe their own size: raw first record, u32 point count, one
// u32 byte count per layer, then the layers. Number of layers for `format`.
std::size_t layer_count(const Format& format);

} // namespace lasmesh::laz
