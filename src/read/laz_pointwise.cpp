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

// A chunk being decoded, one record at a time.
class PointwiseChunk {
public:
    PointwiseChunk(const Format& format, std::span<const std::byte> bytes, std::uint64_t count, std::byte* out)
        : format_(format), bytes_(bytes), count_(count), record_(out) {
        if (count == 0) return;
        const std::size_t length = format.record_length;
        if (bytes.size() < length)
            throw ChunkError(bytes.size(),
                             "ends inside its first (uncompressed) record of " + std::to_string(length) + " bytes");
        std::memcpy(out, bytes.data(), length);
        if (count == 1) return;
        std::size_t at = 0;
        for (const Item& item : format.items) {
            const std::byte* first = out + at;
            switch (item.type) {
            case ItemType::point10: items_.point.emplace(first); break;
            case ItemType::gpstime11: items_.time.emplace(first); break;
            case ItemType::rgb12: items_.rgb.emplace(first); break;
            case ItemType::wavepacket13: items_.wave.emplace(first); break;
            default: items_.bytes.emplace(first, item.size); break;
            }
            at += item.size;
        }
        dec_ = ArithmeticDecoder(bytes.subspan(length));
    }

    bool done() const { return next_ >= count_; }

    void decode_record() {
        record_ += format_.record_length;
        std::byte* field = record_;
        for (const Item& item : format_.items) {
            switch (item.type) {
            case ItemType::point10: items_.point->decode(dec_, field); break;
            case ItemType::gpstime11: items_.time->decode(dec_, field); break;
            case ItemType::rgb12: items_.rgb->decode(dec_, field); break;
            case ItemType::wavepacket13: items_.wave->decode(dec_, field); break;
            default: items_.bytes->decode(dec_, field); break;
            }
            field += item.size;
        }
        if (dec_.overrun())
            throw ChunkError(bytes_.size(), "compressed data ends inside record " + std::to_string(next_) + " of " +
                                                std::to_string(count_) + " (truncated or corrupt)");
        ++next_;
    }

    // The compressed bytes used so far (all of the chunk's once done).
    std::size_t used() const { return count_ == 0 ? 0 : format_.record_length + (count_ > 1 ? dec_.position() : 0); }

private:
    const Format& format_;
    std::span<const std::byte> bytes_;
    std::uint64_t count_;
    std::uint64_t next_ = 1; // record 0 is stored raw
    std::byte* record_;
    PointwiseItems items_;
    ArithmeticDecoder dec_;
};

} // namespace

std::size_t decode_pointwise_chunk(const Format& format, std::span<const std::byte> bytes, std::uint64_t count,
                                   std::byte* out) {
    PointwiseChunk chunk(format, bytes, count, out);
    while (!chunk.done()) chunk.decode_record();
    return chunk.used();
}

void decode_pointwise_pair(const Format& format, std::array<PointwiseJob, 2>& jobs) {
    // Both chunks' records alternate: each record's symbols form one chain of dependent steps
    // (a division, then table look-ups, per symbol), and two chains from independent streams
    // let the processor work on one while the other waits.
    std::array<std::optional<PointwiseChunk>, 2> chunks;
    for (int k = 0; k < 2; ++k) {
        try {
            chunks[k].emplace(format, jobs[k].bytes, jobs[k].count, jobs[k].out);
        } catch (const ChunkError& e) {
            jobs[k].error = e;
        }
    }
    auto step = [&](int k) {
        try {
            chunks[k]->decode_record();
        } catch (const ChunkError& e) {
            jobs[k].error = e;
            chunks[k].reset();
        }
    };
    auto live = [&](int k) { return chunks[k] && !chunks[k]->done(); };
    while (live(0) && live(1)) step(0), step(1);
    for (int k = 0; k < 2; ++k)
        while (live(k)) step(k);
}

} // namespace lasmesh::laz
