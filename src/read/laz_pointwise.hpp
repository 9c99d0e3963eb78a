// SPDX-License-Identifier: Apache-2.0
// Decoding one chunk of a pointwise-compressed LAZ file (LASzip compressors 1 and 2, point
// formats 0-5): the chunk's first record is stored raw, then every following record is coded
// item by item (POINT10, GPSTIME11, RGB12, WAVEPACKET13, BYTE) in one arithmetic stream.
#pragma once

#include "read/arithmetic_decoder.hpp"
#include "read/laz_vlr.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

namespace lasmesh::laz {

// Decodes `count` records from `bytes` into `out` (count * record_length bytes) and returns
// the compressed bytes the chunk used; its models are made in `store`. Throws ChunkError when
// the data ends early.
std::size_t decode_pointwise_chunk(const Format& format, std::span<const std::byte> bytes, std::uint64_t count,
                                   std::byte* out, ModelStore& store);

} // namespace lasmesh::laz
