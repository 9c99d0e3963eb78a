// SPDX-License-Identifier: Apache-2.0
// Decoding one chunk of a layered LAZ file (LASzip compressor 3, point formats 6-10; item
// versions 3 and 4): raw first record, u32 point count, the byte size of every layer, then the
// layers. Each field group is its own arithmetic stream ("layer"), so fields a reader does not
// need could be skipped; a layer of 0 bytes means the field never changes in the chunk.
#pragma once

#include "read/arithmetic_decoder.hpp"
#include "read/laz_vlr.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

namespace lasmesh::laz {

// Decodes the `count` records of the chunk in `bytes` into `out`, with models made in `store`;
// throws ChunkError.
void decode_layered_chunk(const Format& format, std::span<const std::byte> bytes, std::uint64_t count, std::byte* out,
                          ModelStore& store);

} // namespace lasmesh::laz
