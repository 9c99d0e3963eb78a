// Decoding one chunk of a pointwise-compressed LAZ file (LASzip compressors 1 and 2, point
// formats 0-5): the chunk's first record is stored raw, then every following record is coded
// item by item (POINT10, GPSTIME11, RGB12, WAVEPACKET13, BYTE) in one arithmetic stream.
#pragma once

#include "read/laz_vlr.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace lasmesh::laz {

// Decodes `count` records from `bytes` into `out` (count * record_length bytes) and returns
// the compressed bytes the chunk used. Throws ChunkError when the data ends early.
std::size_t decode_pointwise_chunk(const Format& format, std::span<const std::byte> bytes, std::uint64_t count,
                                   std::byte* out);

// One chunk for decode_pointwise_pair: its bytes, record count and output, and the error that
// stopped it, if any.
struct PointwiseJob {
    std::span<const std::byte> bytes;
    std::uint64_t count = 0;
    std::byte* out = nullptr;
    std::optional<ChunkError> error;
};

// Decodes two chunks in one thread, a record of each in turn (the same records as decoding
// them one after the other, faster). An error stops only the chunk it is in.
void decode_pointwise_pair(const Format& format, std::array<PointwiseJob, 2>& jobs);

} // namespace lasmesh::laz
