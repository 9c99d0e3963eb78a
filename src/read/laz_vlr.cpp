// SPDX-License-Identifier: Apache-2.0
// Parsing of the LASzip VLR (layout: laszip.org "LAZ specification"; Isenburg 2013, section 4).
#include "read/laz_vlr.hpp"

#include "byte_order.hpp"
#include "lasmesh/error.hpp"

namespace lasmesh::laz {

std::string item_name(ItemType type) {
    switch (type) {
    case ItemType::byte: return "BYTE";
    case ItemType::point10: return "POINT10";
    case ItemType::gpstime11: return "GPSTIME11";
    case ItemType::rgb12: return "RGB12";
    case ItemType::wavepacket13: return "WAVEPACKET13";
    case ItemType::point14: return "POINT14";
    case ItemType::rgb14: return "RGB14";
    case ItemType::rgbnir14: return "RGBNIR14";
    case ItemType::wavepacket14: return "WAVEPACKET14";
    case ItemType::byte14: return "BYTE14";
    }
    return "item type " + std::to_string(static_cast<unsigned>(type));
}

namespace {

// The fixed size of each item type (extra bytes items have any size).
int fixed_size(ItemType type) {
    switch (type) {
    case ItemType::point10: return 20;
    case ItemType::gpstime11: return 8;
    case ItemType::rgb12: return 6;
    case ItemType::wavepacket13: return 29;
    case ItemType::point14: return 30;
    case ItemType::rgb14: return 6;
    case ItemType::rgbnir14: return 8;
    case ItemType::wavepacket14: return 29;
    default: return -1;
    }
}

bool pointwise_item(ItemType t) {
    return t == ItemType::byte || t == ItemType::point10 || t == ItemType::gpstime11 || t == ItemType::rgb12 ||
           t == ItemType::wavepacket13;
}

} // namespace

Format parse_laszip_vlr(std::span<const std::byte> p, const std::string& source, int point_format,
                        std::uint16_t record_length) {
    auto fail = [&](const std::string& what) { throw_input_error(source, "LASzip VLR: " + what); };
    // u16 compressor, u16 coder, u8 major, u8 minor, u16 revision, u32 options, u32 chunk size,
    // i64 special EVLR count, i64 special EVLR offset, u16 item count, then 6 bytes per item.
    if (p.size() < 34) fail("is " + std::to_string(p.size()) + " bytes, shorter than its 34-byte header");
    Format f;
    const std::uint16_t compressor = load_le<std::uint16_t>(p.data());
    const std::uint16_t coder = load_le<std::uint16_t>(p.data() + 2);
    f.chunk_size = load_le<std::uint32_t>(p.data() + 12);
    const std::uint16_t count = load_le<std::uint16_t>(p.data() + 32);
    if (compressor < 1 || compressor > 3)
        fail("compressor " + std::to_string(compressor) +
             " is not one of 1 (pointwise), 2 (pointwise chunked), 3 (layered chunked)");
    if (coder != 0) fail("coder " + std::to_string(coder) + " is not 0 (arithmetic), the only one LASzip defines");
    f.compressor = static_cast<Compressor>(compressor);
    if (f.chunked() && f.chunk_size == 0) fail("chunk size is 0");
    // LASzip writes 50,000; a fixed size beyond this (16.7 M points) is corruption, and would
    // make a chunk's records too large to hold.
    if (f.chunked() && !f.variable_chunks() && f.chunk_size > (1u << 24))
        fail("chunk size " + std::to_string(f.chunk_size) + " is implausibly large");
    if (p.size() < 34 + 6u * count)
        fail("lists " + std::to_string(count) + " items but is only " + std::to_string(p.size()) + " bytes");
    unsigned total = 0;
    for (unsigned i = 0; i < count; ++i) {
        const std::byte* at = p.data() + 34 + 6 * i;
        Item item{static_cast<ItemType>(load_le<std::uint16_t>(at)), load_le<std::uint16_t>(at + 2),
                  load_le<std::uint16_t>(at + 4)};
        const std::string name = item_name(item.type) + " v" + std::to_string(item.version);
        const int size = fixed_size(item.type);
        const bool known = size > 0 || item.type == ItemType::byte || item.type == ItemType::byte14;
        if (!known)
            fail("item " + std::to_string(i) + " has unknown type " + std::to_string(static_cast<unsigned>(item.type)));
        if (size > 0 ? item.size != size : item.size == 0)
            fail("item " + name + " is " + std::to_string(item.size) + " bytes, expected " + std::to_string(size));
        if (pointwise_item(item.type)) {
            if (f.layered()) fail("item " + name + " cannot be used with the layered compressor 3");
            const bool ok = item.type == ItemType::wavepacket13 ? item.version == 1 : item.version == 2;
            if (!ok)
                fail(
                    "item " + name +
                    " is not supported: lasmesh decodes the item versions current LASzip writes "
                    "(v2; WAVEPACKET13 v1), not those of LASzip 1.x (2011); recompress the file with a current laszip");
        } else {
            if (!f.layered())
                fail("item " + name + " needs the layered compressor 3, not compressor " + std::to_string(compressor));
            if (item.version != 3 && item.version != 4) fail("item " + name + " is not supported (expected v3 or v4)");
        }
        total += item.size;
        f.items.push_back(item);
    }
    if (f.items.empty()) fail("lists no items");
    const ItemType first = f.items.front().type;
    if (first != ItemType::point10 && first != ItemType::point14)
        fail("first item is " + item_name(first) + ", expected POINT10 or POINT14");
    if ((first == ItemType::point14) != (point_format >= 6))
        fail("item " + item_name(first) + " does not match point format " + std::to_string(point_format));
    if (total != record_length)
        fail("items add up to " + std::to_string(total) + " bytes per point, but the header's point record length is " +
             std::to_string(record_length));
    f.record_length = record_length;
    if (f.chunked() && !f.variable_chunks() && std::uint64_t{f.chunk_size} * record_length > max_chunk_record_bytes)
        fail("chunks of " + std::to_string(f.chunk_size) + " points of " + std::to_string(record_length) +
             " bytes would not fit in memory");
    return f;
}

} // namespace lasmesh::laz
