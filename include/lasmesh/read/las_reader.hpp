// SPDX-License-Identifier: Apache-2.0
// A streaming LAS reader: header and VLRs first, then the point records in caller-sized chunks of
// raw bytes, in one forward pass with no seeks (files, pipes and compressed streams alike).
// LAZ (LASzip-compressed LAS) is decoded on the way: the header then describes the
// uncompressed records, and read_records hands out the same bytes a LAS file would hold.
#pragma once

#include "lasmesh/read/input_stream.hpp"
#include "lasmesh/read/las_header.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace lasmesh {

namespace laz {
class LazDecoder;
}

class LasReader {
  public:
    // Opens `path` ("-" for standard input) and reads the header; throws Error (input).
    explicit LasReader(const std::string& path);
    ~LasReader();

    const LasHeader& header() const { return header_; }
    const InputStream& stream() const { return stream_; }
    std::uint64_t records_read() const { return records_read_; }
    std::uint64_t records_left() const { return header_.point_count - records_read_; }

    // Fills `dst` with up to dst.size() / point_record_length whole records and returns how many;
    // 0 once every record the header promises has been read. Throws Error (input) naming the
    // records read and expected when the input ends early, or when a compressed stream fails its
    // end-of-stream check (read through to the end after the last record).
    std::size_t read_records(std::span<std::byte> dst);

    // Bytes after the last promised record, known once it is read: records the header does not
    // count (a wrong point count) or junk. Never meshed; the caller warns.
    std::uint64_t trailing_bytes() const { return trailing_bytes_; }
    // LAZ from a file: what its chunk table holds past the header's count ("1 more chunk"),
    // never read; empty otherwise.
    std::string laz_beyond_header() const;

  private:
    InputStream stream_;
    LasHeader header_;
    std::uint64_t records_read_ = 0;
    std::uint64_t trailing_bytes_ = 0;
    std::unique_ptr<laz::LazDecoder> laz_; // set for LAZ input
};

// "warning: 20 bytes (0 whole records of 34 bytes) follow the 1000 point records the header
// counts; they were not read (the header's point count is wrong?)", the like for LAZ chunks
// past the header's count, or "" when none follow.
std::string trailing_warning(const LasReader& reader);

} // namespace lasmesh
