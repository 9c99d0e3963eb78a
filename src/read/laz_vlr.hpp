// SPDX-License-Identifier: Apache-2.0
// The LASzip VLR (user id "laszip encoded", record 22204): which compressor wrote the points,
// the chunk size, and the list of items (field groups) that make up a point record.
// Layout from the LASzip format description (laszip.org; Isenburg 2013, section 4).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace lasmesh::laz {

enum class ItemType : std::uint16_t {
    byte = 0, // extra bytes, pointwise
    point10 = 6,
    gpstime11 = 7,
    rgb12 = 8,
    wavepacket13 = 9,
    point14 = 10,
    rgb14 = 11,
    rgbnir14 = 12,
    wavepacket14 = 13,
    byte14 = 14, // extra bytes, layered
};

struct Item {
    ItemType type;
    std::uint16_t size;
    std::uint16_t version;
};

enum class Compressor : std::uint16_t { pointwise = 1, pointwise_chunked = 2, layered_chunked = 3 };

constexpr std::uint32_t variable_chunk_size = 0xFFFFFFFFu;
// A chunk is decoded whole into memory; more than this many bytes of records is refused.
constexpr std::uint64_t max_chunk_record_bytes = std::uint64_t{1} << 28;

struct Format {
    Compressor compressor = Compressor::pointwise_chunked;
    std::uint32_t chunk_size = 50000; // points per chunk, or variable_chunk_size
    std::vector<Item> items;
    std::uint16_t record_length = 0; // sum of the item sizes
    bool chunked() const { return compressor != Compressor::pointwise; }
    bool layered() const { return compressor == Compressor::layered_chunked; }
    bool variable_chunks() const { return chunk_size == variable_chunk_size; }
};

// Parses and checks the VLR payload against the header's point format and record length.
// Throws Error (input) naming `source` for anything this decoder cannot decode: unknown
// compressor or coder, item version 1 (LASzip 1.x), items that do not add up to the record.
Format parse_laszip_vlr(std::span<const std::byte> payload, const std::string& source, int point_format,
                        std::uint16_t record_length);

std::string item_name(ItemType type);

// Thrown by the chunk decoders: where in the chunk (bytes from its start) and what went wrong;
// the caller adds the file, the chunk number and the file offset.
struct ChunkError : std::runtime_error {
    ChunkError(std::size_t at, const std::string& what) : std::runtime_error(what), offset(at) {}
    std::size_t offset;
};

} // namespace lasmesh::laz
