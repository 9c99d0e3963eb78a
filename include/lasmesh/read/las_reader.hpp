// A streaming LAS reader: header and VLRs first, then the point records in caller-sized chunks of
// raw bytes, in one forward pass with no seeks (files, pipes and compressed streams alike).
#pragma once

#include "lasmesh/read/input_stream.hpp"
#include "lasmesh/read/las_header.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace lasmesh {

class LasReader {
public:
    // Opens `path` ("-" for standard input) and reads the header; throws Error (input).
    explicit LasReader(const std::string& path);

    const LasHeader& header() const { return header_; }
    const InputStream& stream() const { return stream_; }
    std::uint64_t records_read() const { return records_read_; }
    std::uint64_t records_left() const { return header_.point_count - records_read_; }

    // Fills `dst` with up to dst.size() / point_record_length whole records and returns how many;
    // 0 once every record the header promises has been read (bytes after them are ignored).
    // Throws Error (input) naming the records read and expected when the input ends early.
    std::size_t read_records(std::span<std::byte> dst);

private:
    InputStream stream_;
    LasHeader header_;
    std::uint64_t records_read_ = 0;
};

} // namespace lasmesh
