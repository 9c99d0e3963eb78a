// SPDX-License-Identifier: Apache-2.0
// A streaming LAS reader: header and VLRs first, then the point records in caller-sized chunks of
// raw bytes, in one forward pass with no seeks (files, pipes and compressed streams alike).
// LAZ (LASzip-compressed LAS) is decoded on the way: the header then describes the
// uncompressed records, and read_records hands out the same bytes a LAS file would hold.
//
//     lasmesh::LasReader reader("deck.laz");          // or "-": standard input, also gzip/bzip2/xz/zstd
//     std::vector<lasmesh::LasPoint> points(65536);
//     while (std::size_t n = lasmesh::read_points(reader, points))
//         for (std::size_t i = 0; i < n; ++i) use(points[i].position, points[i].color);
//     // every failure throws lasmesh::Error (input) naming the file, the offset or record
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace lasmesh {

class InputStream;
namespace laz {
class LazDecoder;
}

// A variable length record as listed in the header area; its payload is read past, not kept
// (except the LASzip VLR's, which the LAZ decoder needs, the coordinate system's and COPC's info).
struct Vlr {
    std::string user_id; // up to 16 characters, trailing NULs removed
    std::uint16_t record_id = 0;
    std::uint16_t length = 0;    // payload bytes after the 54-byte VLR header (an EVLR's: at most 65535)
    std::string description;     // up to 32 characters, trailing NULs removed
    std::vector<std::byte> data; // the payload, kept for the LASzip, coordinate system and COPC info VLRs
};

struct LasHeader {
    std::uint8_t version_major = 1;
    std::uint8_t version_minor = 2;
    std::uint16_t global_encoding = 0;
    std::string system_identifier;
    std::string generating_software;
    std::uint16_t header_size = 0;
    std::uint32_t offset_to_point_data = 0;
    std::uint32_t vlr_count = 0;
    std::uint8_t point_format = 0; // 0-10, with the LAZ compression bits 6 and 7 cleared
    bool compressed = false;       // LAZ: a LASzip VLR (and the compression bit)
    std::uint16_t point_record_length = 0;
    std::uint32_t legacy_point_count = 0;
    // The number of records to read: the 64-bit count for LAS 1.4, the legacy count before.
    std::uint64_t point_count = 0;
    std::array<double, 3> scale{};
    std::array<double, 3> offset{};
    std::array<double, 3> min{};
    std::array<double, 3> max{};
    std::vector<Vlr> vlrs;
    // LAS 1.4's extended VLRs, after the point records: where they start and how many, and those
    // of the coordinate system (LASF_Projection) with their payloads, read from a file (not from a
    // pipe or a compressed stream, which cannot seek there).
    std::uint64_t evlr_start = 0;
    std::uint32_t evlr_count = 0;
    std::vector<Vlr> crs_evlrs;
    // Where data the format puts after the point records starts (LAS 1.3 waveform packets, LAS
    // 1.4 extended VLRs); 0 when none: then any bytes after the last record are unexpected.
    std::uint64_t start_after_points = 0;
};

class LasReader {
  public:
    // Opens `path` ("-" for standard input) and reads the header; throws Error (input).
    explicit LasReader(const std::string& path);
    ~LasReader();

    const LasHeader& header() const { return header_; }
    const InputStream& stream() const { return *stream_; } // its name, bytes read so far
    std::uint64_t records_read() const { return records_read_; }
    std::uint64_t records_left() const { return header_.point_count - records_read_; }

    // Fills `dst` with up to dst.size() / point_record_length whole records and returns how many;
    // 0 once every record the header promises has been read. Throws Error (input) naming the
    // records read and expected when the input ends early, or when a compressed stream fails its
    // end-of-stream check (read through to the end after the last record).
    std::size_t read_records(std::span<std::byte> dst);

    // LAZ from a file: read only the chunks that start at `offsets` (ascending; a COPC file's
    // octree nodes that meet a region), seeking past the rest. Before the first read; the
    // header's point count becomes theirs. Throws Error (input) for an offset where no chunk
    // starts, or for input that is not LAZ read from a file.
    void read_only_chunks(const std::vector<std::uint64_t>& offsets);

    // Bytes after the last promised record, known once it is read: records the header does not
    // count (a wrong point count) or junk. Never meshed; the caller warns.
    std::uint64_t trailing_bytes() const { return trailing_bytes_; }
    // LAZ from a file: what its chunk table holds past the header's count ("1 more chunk"),
    // never read; empty otherwise.
    std::string laz_beyond_header() const;

  private:
    std::unique_ptr<InputStream> stream_;
    LasHeader header_;
    std::uint64_t records_read_ = 0;
    std::uint64_t trailing_bytes_ = 0;
    std::unique_ptr<laz::LazDecoder> laz_; // set for LAZ input
};

// "warning: 20 bytes (0 whole records of 34 bytes) follow the 1000 point records the header
// counts; they were not read (the header's point count is wrong?)", the like for LAZ chunks
// past the header's count, or "" when none follow.
std::string trailing_warning(const LasReader& reader);

// One decoded point: its position in the file's coordinates (scale and offset applied) and its
// colour as stored (16-bit words; zero when the point format has no colour).
struct LasPoint {
    std::array<double, 3> position{};
    std::array<std::uint16_t, 3> color{};
};

// Reads and decodes up to dst.size() points; returns how many, 0 once every record is read.
// Throws Error (input) as read_records does.
std::size_t read_points(LasReader& reader, std::span<LasPoint> dst);

} // namespace lasmesh
