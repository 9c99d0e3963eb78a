// SPDX-License-Identifier: Apache-2.0
// One pointwise chunk: raw first record, then all items of each record from one stream.
#include "read/laz_pointwise.hpp"

#include "read/laz_items_v2.hpp"

#include <cstring>
#include <optional>

namespace lasmesh::laz {

namespace {

// The item decoders of one record layout, in item order. Each item kind appears at most once
// (the VLR check guarantees the first is POINT10); a switch per item keeps the hot loop free of
// virtual calls.
struct PointwiseItems {
    std::optional<Point10Decoder> point;
    std::optional<GpsTime11Decoder> time;
    std::optional<Rgb12Decoder> rgb;
    std::optional<WavePacketDecoder> wave;
    std::optional<ByteDecoder> bytes;
};

} // namespace

std::size_t decode_pointwise_chunk(const Format& format, std::span<const std::byte> bytes, std::uint64_t count,
                                   std::byte* out, ModelStore& store) {
    if (count == 0) return 0;
    const std::size_t length = format.record_length;
    if (bytes.size() < length)
        throw ChunkError(bytes.size(),
                         "ends inside its first (uncompressed) record of " + std::to_string(length) + " bytes");
    std::memcpy(out, bytes.data(), length);
    if (count == 1) return length;

    PointwiseItems items;
    std::size_t at = 0;
    for (const Item& item : format.items) {
        const std::byte* first = out + at;
        switch (item.type) {
        case ItemType::point10: items.point.emplace(first, store); break;
        case ItemType::gpstime11: items.time.emplace(first, store); break;
        case ItemType::rgb12: items.rgb.emplace(first); break;
        case ItemType::wavepacket13: items.wave.emplace(first, store); break;
        default: items.bytes.emplace(first, item.size); break;
        }
        at += item.size;
    }
    ArithmeticDecoder dec(bytes.subspan(length), store);
    std::byte* record = out;
    for (std::uint64_t i = 1; i < count; ++i) {
        record += length;
        std::byte* field = record;
        for (const Item& item : format.items) {
            switch (item.type) {
            case ItemType::point10: items.point->decode(dec, field); break;
            case ItemType::gpstime11: items.time->decode(dec, field); break;
            case ItemType::rgb12: items.rgb->decode(dec, field); break;
            case ItemType::wavepacket13: items.wave->decode(dec, field); break;
            default: items.bytes->decode(dec, field); break;
            }
            field += item.size;
        }
        if (dec.overrun())
            throw ChunkError(bytes.size(), "compressed data ends inside record " + std::to_string(i) + " of " +
                                               std::to_string(count) + " (truncated or corrupt)");
    }
    return length + dec.position();
}

} // namespace lasmesh::laz
