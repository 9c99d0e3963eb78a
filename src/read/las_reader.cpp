// LasReader: whole records straight from the stream into the caller's buffer.
#include "lasmesh/read/las_reader.hpp"

#include "lasmesh/error.hpp"
#include "read/laz_decoder.hpp"

#include <algorithm>

namespace lasmesh {

LasReader::LasReader(const std::string& path) : stream_(path), header_(read_las_header(stream_)) {
    if (header_.compressed) laz_ = std::make_unique<laz::LazDecoder>(stream_, header_, path);
}

LasReader::~LasReader() = default;

std::size_t LasReader::read_records(std::span<std::byte> dst) {
    const std::size_t length = header_.point_record_length;
    const std::uint64_t wanted = std::min<std::uint64_t>(dst.size() / length, records_left());
    if (wanted == 0) return 0;
    const std::size_t bytes = static_cast<std::size_t>(wanted) * length;
    if (laz_) {
        const std::size_t got = laz_->read(dst.data(), static_cast<std::size_t>(wanted));
        records_read_ += got;
        if (got < wanted)
            throw_input_error(stream_.name(), "LAZ chunks hold " + std::to_string(records_read_) +
                                                  " point records, but the header promises " +
                                                  std::to_string(header_.point_count));
        return got;
    }
    const std::size_t got = stream_.read(dst.data(), bytes);
    if (got < bytes) {
        const std::uint64_t whole = records_read_ + got / length;
        std::string partial = got % length ? " and " + std::to_string(got % length) + " bytes of record " +
                                                 std::to_string(whole)
                                           : "";
        throw_input_error(stream_.name(),
                          "ends at byte " + std::to_string(stream_.position()) + " after " +
                              std::to_string(whole) + " whole point records" + partial + ", but the header promises " +
                              std::to_string(header_.point_count) + " records of " + std::to_string(length) +
                              " bytes (truncated file or pipe?)");
    }
    records_read_ += wanted;
    return static_cast<std::size_t>(wanted);
}

} // namespace lasmesh
