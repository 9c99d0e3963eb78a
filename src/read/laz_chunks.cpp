// SPDX-License-Identifier: Apache-2.0
// Chunk table decoding (see the header).
#include "read/laz_chunks.hpp"

#include "byte_order.hpp"
#include "lasmesh/error.hpp"
#include "read/arithmetic_decoder.hpp"

namespace lasmesh::laz {

std::size_t layer_count(const Format& format) {
    std::size_t layers = 0;
    for (const Item& item : format.items) {
        switch (item.type) {
        case ItemType::point14: layers += 9; break; // XY+returns, Z, class, flags, intensity, angle, user, source, time
        case ItemType::rgbnir14: layers += 2; break;
        case ItemType::byte14: layers += item.size; break; // one layer per extra byte
        default: layers += 1; break;
        }
    }
    return layers;
}

std::vector<Chunk> decode_chunk_table(std::span<const std::byte> table, const Format& format, std::uint64_t point_count,
                                      std::uint64_t first_chunk_offset, std::uint64_t table_offset,
                                      const std::string& source, std::string& beyond) {
    const std::string where = "chunk table at byte " + std::to_string(table_offset);
    if (table.size() < 8) throw_input_error(source, "ends inside the " + where);
    const std::uint32_t version = load_le<std::uint32_t>(table.data());
    const std::uint32_t count = load_le<std::uint32_t>(table.data() + 4);
    if (version != 0) throw_input_error(source, where + " has version " + std::to_string(version) + ", expected 0");
    // Every chunk holds at least one point, except an empty file's (even when the header's count
    // is too low: a chunk holds at most 2^32 points).
    if (count > (point_count + 1) * 2 && count > point_count + (std::uint64_t{1} << 20))
        throw_input_error(source, where + " lists " + std::to_string(count) + " chunks for " +
                                      std::to_string(point_count) + " points (corrupt table)");
    std::vector<Chunk> chunks(count);
    if (count == 0 && point_count == 0) return chunks; // nothing coded after the count
    ModelStore store;
    ArithmeticDecoder dec(table.subspan(8), store);
    IntegerDecoder ic(32, 2);
    std::uint64_t offset = first_chunk_offset, points = 0;
    std::int32_t last_points = 0, last_bytes = 0;
    std::uint32_t kept = 0; // the chunks the header's count reaches into
    for (std::uint32_t i = 0; i < count; ++i) {
        Chunk& c = chunks[i];
        if (format.variable_chunks()) {
            last_points = ic.decode(dec, last_points, 0);
            c.points = static_cast<std::uint32_t>(last_points);
        } else {
            c.points = format.chunk_size; // the last may hold fewer: set below
        }
        last_bytes = ic.decode(dec, last_bytes, 1);
        c.bytes = static_cast<std::uint32_t>(last_bytes);
        c.offset = offset;
        if (c.points == 0 || !plausible_points(c.points, c.bytes) ||
            c.points * format.record_length > max_chunk_record_bytes)
            throw_input_error(source, where + ": chunk " + std::to_string(i + 1) + " claims " +
                                          std::to_string(c.points) + " points in " + std::to_string(c.bytes) +
                                          " bytes (corrupt table)");
        if (points < point_count) kept = i + 1;
        offset += c.bytes;
        points += c.points;
    }
    if (dec.overrun()) throw_input_error(source, "ends inside the " + where);
    if (offset > table_offset)
        throw_input_error(source, where + ": its " + std::to_string(count) + " chunks would end at byte " +
                                      std::to_string(offset) + ", after the table itself (corrupt table)");
    // Fixed-size chunks: the last one the header reaches holds what is left of its count.
    if (!format.variable_chunks() && count > 0) {
        std::uint64_t before = 0;
        for (std::uint32_t i = 0; i + 1 < kept; ++i) before += chunks[i].points;
        if (kept > 0 && point_count > before)
            chunks[kept - 1].points = std::min<std::uint64_t>(format.chunk_size, point_count - before);
        points = 0;
        for (std::uint32_t i = 0; i < kept; ++i) points += chunks[i].points;
    }
    if (points < point_count)
        throw_input_error(source, where + ": its " + std::to_string(count) + " chunks hold " + std::to_string(points) +
                                      " points, but the header promises " + std::to_string(point_count));
    if (format.variable_chunks() && points > point_count) // the chunks' counts are stored: exact
        beyond = std::to_string(points - point_count) + " more points";
    else if (kept < count)
        beyond = std::to_string(count - kept) + " more chunk" + (count - kept > 1 ? "s" : "");
    chunks.resize(kept);
    return chunks;
}

} // namespace lasmesh::laz
