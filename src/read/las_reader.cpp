// SPDX-License-Identifier: Apache-2.0
// LasReader: whole records straight from the stream into the caller's buffer.
#include "lasmesh/las_reader.hpp"

#include "lasmesh/error.hpp"
#include "read/input_stream.hpp"
#include "read/las_header.hpp"
#include "read/las_point.hpp"
#include "read/laz_decoder.hpp"

#include <algorithm>
#include <vector>

namespace lasmesh {

namespace {
// A header that fails to parse on a compressed stream may be the decoder's fault (a damaged block
// whose check comes at its end): run the decoder on, and report its error when it has one.
LasHeader read_header(InputStream& stream) {
    try {
        return read_las_header(stream);
    } catch (const Error&) {
        // Bounded: a large stream of something else need not be decoded to its end for this.
        if (stream.compression() != Compression::none) stream.skip(std::uint64_t{64} << 20); // throws the codec's error
        throw;
    }
}
} // namespace

LasReader::LasReader(const std::string& path)
    : stream_(std::make_unique<InputStream>(path)), header_(read_header(*stream_)) {
    if (path != "-" && stream_->compression() == Compression::none) read_crs_evlrs(path, header_);
    if (header_.compressed) laz_ = std::make_unique<laz::LazDecoder>(*stream_, header_, path);
}

LasReader::~LasReader() = default;

std::string LasReader::laz_beyond_header() const {
    return laz_ ? laz_->beyond_header() : std::string();
}

void LasReader::read_only_chunks(const std::vector<std::uint64_t>& offsets) {
    if (!laz_ || records_read_ > 0)
        throw_input_error(stream_->name(), "only LAZ read from its start can be read a few chunks at a time");
    header_.point_count = laz_->read_only_chunks(offsets);
}

std::size_t LasReader::read_records(std::span<std::byte> dst) {
    const std::size_t length = header_.point_record_length;
    const std::uint64_t wanted = std::min<std::uint64_t>(dst.size() / length, records_left());
    if (wanted == 0) return 0;
    const std::size_t bytes = static_cast<std::size_t>(wanted) * length;
    if (laz_) {
        const std::size_t got = laz_->read(dst.data(), static_cast<std::size_t>(wanted));
        records_read_ += got;
        if (got < wanted)
            throw_input_error(stream_->name(), "LAZ chunks hold " + std::to_string(records_read_) +
                                                   " point records, but the header promises " +
                                                   std::to_string(header_.point_count));
        return got;
    }
    const std::size_t got = stream_->read(dst.data(), bytes);
    if (got < bytes) {
        const std::uint64_t whole = records_read_ + got / length;
        std::string partial =
            got % length ? " and " + std::to_string(got % length) + " bytes of record " + std::to_string(whole) : "";
        throw_input_error(stream_->name(), "ends at byte " + std::to_string(stream_->position()) + " after " +
                                               std::to_string(whole) + " whole point records" + partial +
                                               ", but the header promises " + std::to_string(header_.point_count) +
                                               " records of " + std::to_string(length) +
                                               " bytes (truncated file or pipe?)");
    }
    records_read_ += wanted;
    // After the last promised record: verify the codec's end and count what follows.
    if (records_left() == 0) trailing_bytes_ = stream_->drain();
    return static_cast<std::size_t>(wanted);
}

std::string trailing_warning(const LasReader& reader) {
    if (!reader.laz_beyond_header().empty())
        return "warning: " + reader.stream().name() + ": its LAZ chunk table holds " + reader.laz_beyond_header() +
               " after the " + std::to_string(reader.header().point_count) +
               " points the header counts; they were left out (is the header's point count wrong?)";
    const std::uint64_t bytes = reader.trailing_bytes(), length = reader.header().point_record_length;
    // LAS 1.3 waveform packets and 1.4 extended VLRs belong after the records: not a warning.
    if (bytes == 0 || reader.header().start_after_points != 0) return "";
    return "warning: " + reader.stream().name() + ": " + std::to_string(bytes) + " bytes (" +
           std::to_string(bytes / length) + " whole records of " + std::to_string(length) + " bytes) follow the " +
           std::to_string(reader.header().point_count) +
           " point records the header counts and were left out (is the header's point count wrong?)";
}

std::size_t read_points(LasReader& reader, std::span<LasPoint> dst) {
    const PointDecoder decoder(reader.header());
    std::vector<std::byte> records(std::min<std::size_t>(dst.size(), 1 << 16) * decoder.record_length);
    std::size_t done = 0;
    while (done < dst.size()) {
        const std::size_t want = std::min(dst.size() - done, records.size() / decoder.record_length);
        const std::size_t got = reader.read_records({records.data(), want * decoder.record_length});
        for (std::size_t i = 0; i < got; ++i) {
            const std::byte* record = records.data() + i * decoder.record_length;
            dst[done + i].position = decoder.position(record);
            dst[done + i].color = decoder.has_color() ? decoder.color(record) : Rgb16{};
        }
        done += got;
        if (got < want) break;
    }
    return done;
}

} // namespace lasmesh
