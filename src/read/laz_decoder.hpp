// SPDX-License-Identifier: Apache-2.0
// LazDecoder: the point records of a LAZ file, decoded chunk by chunk behind LasReader.
// From a file the chunk table is read first (a second handle seeks to it) and batches of
// chunks are decoded in parallel with TBB; the chunks themselves are still read in order from
// the forward-only stream. From a pipe there is no table: layered chunks (compressor 3) state
// their own sizes and are decoded in batches too; pointwise chunks of fixed size are decoded
// one after the other, each ending where its arithmetic stream ends; variable-size pointwise
// chunks cannot be found without the table and are refused with advice to give a file path.
#pragma once

#include "read/arithmetic_decoder.hpp"
#include "read/input_stream.hpp"
#include "read/las_header.hpp"
#include "read/laz_chunks.hpp"
#include "read/laz_vlr.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace lasmesh::laz {

class LazDecoder {
  public:
    // `stream` is at the offset to point data; `path` reopens the file for the chunk table.
    LazDecoder(InputStream& stream, const LasHeader& header, const std::string& path);

    // Copies up to `records` decoded records to `dst`; returns how many (0 once all are out).
    std::size_t read(std::byte* dst, std::size_t records);

    // Reads and decodes only the chunks that start at `offsets` (ascending; a COPC file's nodes
    // that meet a region, read/copc.hpp), skipping the bytes between them; returns their point
    // count. Before the first read, from a file (it needs the chunk table). Throws Error (input)
    // naming the offset that starts no chunk.
    std::uint64_t read_only_chunks(const std::vector<std::uint64_t>& offsets);

    const Format& format() const { return format_; }
    // What the chunk table holds past the header's point count ("1 more chunk", "10000 more
    // points"), never decoded; empty when nothing (or when there is no table: a pipe).
    const std::string& beyond_header() const { return beyond_header_; }

  private:
    struct Pending {
        std::vector<std::byte> bytes; // compressed chunk
        Chunk chunk;
        std::size_t index = 0;
    };
    void decode_next_batch();
    bool next_chunk_bytes(Pending& p); // table or self-describing chunks; false at the end
    void decode_pointwise_sequential();
    void read_exactly(std::byte* dst, std::size_t size, std::uint64_t chunk_index, const char* what);
    [[noreturn]] void chunk_error(std::size_t index, const Chunk& chunk, std::uint64_t at,
                                  const std::string& what) const;

    InputStream& stream_;
    const std::string source_;
    Format format_;
    std::uint64_t point_count_;
    std::uint64_t points_started_ = 0; // points in chunks taken from the stream so far
    std::size_t chunks_started_ = 0;
    // Each thread's symbol models, reused from chunk to chunk (ModelStore).
    tbb::enumerable_thread_specific<ModelStore> stores_;
    std::vector<Chunk> table_; // empty when decoding without the table
    std::vector<char> wanted_; // per chunk of the table: read it; empty: all are
    bool have_table_ = false;
    std::string beyond_header_;
    std::vector<std::byte> carry_; // pipe, pointwise: bytes read past the last chunk's end
    // Decoded records. Grown without zero-filling (filling them cost about 3% of decoding): the
    // item decoders write every byte of every record (their sizes add up to the record length),
    // and a chunk that fails to decode is reported, never handed out.
    class Records {
      public:
        std::byte* data() { return data_.get(); }
        std::size_t size() const { return size_; }
        bool empty() const { return size_ == 0; }
        void clear() { size_ = 0; }
        void resize_for_overwrite(std::size_t n) { // keeps no old contents
            if (n > capacity_) {
                data_.reset();         // the old block goes before the new one comes
                capacity_ = size_ = 0; // (stays consistent if the allocation throws)
                data_ = std::make_unique_for_overwrite<std::byte[]>(n);
                capacity_ = n;
            }
            size_ = n;
        }

      private:
        std::unique_ptr<std::byte[]> data_;
        std::size_t size_ = 0, capacity_ = 0;
    };
    Records decoded_;
    std::size_t decoded_at_ = 0; // bytes of decoded_ handed out
};

} // namespace lasmesh::laz
