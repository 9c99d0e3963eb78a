// SPDX-License-Identifier: Apache-2.0
// LazDecoder: chunk table, batches of chunks decoded in parallel, sequential fallbacks.
#include "read/laz_decoder.hpp"

#include "byte_order.hpp"
#include "lasmesh/error.hpp"
#include "read/laz_layered.hpp"
#include "read/laz_pointwise.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <fcntl.h>
#include <optional>
#include <unistd.h>

namespace lasmesh::laz {

namespace {

constexpr std::size_t batch_points = 1u << 20; // decode about a million points per batch

const Vlr* find_laszip_vlr(const LasHeader& h) {
    for (const Vlr& v : h.vlrs)
        if (v.user_id == "laszip encoded" && v.record_id == 22204) return &v;
    return nullptr;
}

// A second, read-only handle on the file for the chunk table; closed at scope exit.
class FileHandle {
  public:
    explicit FileHandle(const std::string& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {}
    ~FileHandle() {
        if (fd_ >= 0) ::close(fd_);
    }
    FileHandle(const FileHandle&) = delete;
    FileHandle& operator=(const FileHandle&) = delete;
    bool ok() const { return fd_ >= 0; }
    // Reads up to `size` bytes at `offset`; returns how many there were.
    std::size_t read_at(std::uint64_t offset, std::byte* dst, std::size_t size) const {
        std::size_t got = 0;
        while (got < size) {
            const ssize_t n = ::pread(fd_, dst + got, size - got, static_cast<off_t>(offset + got));
            if (n <= 0) break;
            got += static_cast<std::size_t>(n);
        }
        return got;
    }

  private:
    int fd_;
};

} // namespace

LazDecoder::LazDecoder(InputStream& stream, const LasHeader& header, const std::string& path)
    : stream_(stream), source_(stream.name()), point_count_(header.point_count) {
    const Vlr* vlr = find_laszip_vlr(header);
    if (!vlr) throw_input_error(source_, "is LAZ (point format compression bit set) but has no LASzip VLR");
    format_ = parse_laszip_vlr(vlr->data, source_, header.point_format, header.point_record_length);
    if (!format_.chunked()) return; // compressor 1: the points follow directly, no table

    const std::uint64_t pointer_at = stream_.position();
    std::byte raw[8];
    read_exactly(raw, 8, 0, "the chunk table offset");
    std::int64_t table_offset = load_le<std::int64_t>(raw);
    const std::uint64_t first_chunk = pointer_at + 8;

    // No points, no chunks: LASzip writes no table then (its offset is the end of the file), so
    // none is read, from a file as from a pipe.
    if (point_count_ == 0) return;
    // The table needs a seek: only for a plain file opened by path.
    const std::optional<std::uint64_t> file_size = stream_.raw_size();
    if (path == "-" || stream_.compression() != Compression::none || !file_size) {
        if (!format_.layered() && format_.variable_chunks())
            throw_input_error(source_,
                              "is LAZ with variable-size pointwise chunks, which cannot be found without the "
                              "chunk table at the end of the file: give lasmesh the file path instead of a pipe");
        return;
    }
    FileHandle file(path);
    if (!file.ok()) throw_input_error(source_, "cannot be opened a second time to read the LAZ chunk table");
    if (table_offset == -1) {
        // Writers that could not seek back store the table offset in the file's last 8 bytes.
        if (*file_size < 8 || file.read_at(*file_size - 8, raw, 8) < 8)
            throw_input_error(source_, "has no LAZ chunk table offset at its end");
        table_offset = load_le<std::int64_t>(raw);
    }
    if (table_offset < static_cast<std::int64_t>(first_chunk) || static_cast<std::uint64_t>(table_offset) > *file_size)
        throw_input_error(source_, "LAZ chunk table offset " + std::to_string(table_offset) + " (at byte " +
                                       std::to_string(pointer_at) + ") lies outside the point data, bytes " +
                                       std::to_string(first_chunk) + " to " + std::to_string(*file_size));
    // Generous upper bound on the coded table: a few bytes per value.
    const std::uint64_t max_chunks = point_count_ + 1;
    const std::uint64_t want = std::min<std::uint64_t>(*file_size - table_offset, 8 + 20 * max_chunks + 64);
    std::vector<std::byte> table(static_cast<std::size_t>(want));
    table.resize(file.read_at(static_cast<std::uint64_t>(table_offset), table.data(), table.size()));
    table_ = decode_chunk_table(table, format_, point_count_, first_chunk, static_cast<std::uint64_t>(table_offset),
                                source_, beyond_header_);
    have_table_ = true;
}

std::uint64_t LazDecoder::read_only_chunks(const std::vector<std::uint64_t>& offsets) {
    if (!have_table_ || chunks_started_ > 0)
        throw_input_error(source_, "only a LAZ file read by path, from its start, can be read a few chunks at a time");
    wanted_.assign(table_.size(), 0);
    point_count_ = 0;
    for (const std::uint64_t offset : offsets) {
        const auto at = std::lower_bound(table_.begin(), table_.end(), offset,
                                         [](const Chunk& c, std::uint64_t o) { return c.offset < o; });
        if (at == table_.end() || at->offset != offset)
            throw_input_error(source_, "no LAZ chunk starts at byte " + std::to_string(offset) +
                                           " (a COPC node's chunk, by its hierarchy): the file is damaged, or changed "
                                           "since it was planned");
        char& want = wanted_[static_cast<std::size_t>(at - table_.begin())];
        if (!want) point_count_ += at->points;
        want = 1;
    }
    return point_count_;
}

void LazDecoder::read_exactly(std::byte* dst, std::size_t size, std::uint64_t chunk_index, const char* what) {
    const std::uint64_t at = stream_.position();
    const std::size_t got = stream_.read(dst, size);
    if (got < size)
        throw_input_error(source_, "ends at byte " + std::to_string(at + got) + " inside " + what + " of LAZ chunk " +
                                       std::to_string(chunk_index + 1) + " (bytes " + std::to_string(at) + " to " +
                                       std::to_string(at + size) + "): truncated file or pipe?");
}

void LazDecoder::chunk_error(std::size_t index, const Chunk& chunk, std::uint64_t at, const std::string& what) const {
    std::string which = "LAZ chunk " + std::to_string(index + 1);
    if (have_table_) which += " of " + std::to_string(table_.size());
    throw_input_error(source_, which + " (points " + std::to_string(chunk.points) + ", bytes " +
                                   std::to_string(chunk.offset) + " to " + std::to_string(chunk.offset + chunk.bytes) +
                                   "): " + what + " at byte " + std::to_string(at));
}

bool LazDecoder::next_chunk_bytes(Pending& p) {
    if (points_started_ >= point_count_) return false;
    p.index = chunks_started_;
    if (have_table_) {
        while (!wanted_.empty() && chunks_started_ < table_.size() && !wanted_[chunks_started_]) ++chunks_started_;
        if (chunks_started_ >= table_.size()) return false;
        p.chunk = table_[chunks_started_];
        const std::uint64_t gap = p.chunk.offset - std::min(p.chunk.offset, stream_.position());
        stream_.skip(gap);
        p.bytes.resize(static_cast<std::size_t>(p.chunk.bytes));
        read_exactly(p.bytes.data(), p.bytes.size(), p.index, "the compressed data");
    } else {
        // Layered chunk without the table: raw record, point count, layer sizes, layers.
        p.chunk.offset = stream_.position();
        const std::size_t head = format_.record_length + 4u + 4u * layer_count(format_);
        p.bytes.resize(head);
        read_exactly(p.bytes.data(), head, p.index, "the header");
        const std::uint32_t count = load_le<std::uint32_t>(p.bytes.data() + format_.record_length);
        std::uint64_t body = 0;
        for (std::size_t i = format_.record_length + 4u; i < head; i += 4)
            body += load_le<std::uint32_t>(p.bytes.data() + i);
        p.chunk.points = count;
        p.chunk.bytes = head + body;
        const std::uint64_t left = point_count_ - points_started_;
        if (count == 0 || count > left ||
            (!format_.variable_chunks() && count != std::min<std::uint64_t>(format_.chunk_size, left)))
            chunk_error(p.index, p.chunk, p.chunk.offset + format_.record_length,
                        "it holds " + std::to_string(count) + " points, but " + std::to_string(left) +
                            " points are left (chunk size " + std::to_string(format_.chunk_size) + ")");
        if (body > (std::uint64_t{1} << 32) || !plausible_points(count, head + body) ||
            count * format_.record_length > max_chunk_record_bytes)
            chunk_error(p.index, p.chunk, p.chunk.offset + format_.record_length + 4,
                        "its layer sizes are implausible for " + std::to_string(count) + " points");
        // Grown as the bytes arrive: corrupt layer sizes must not allocate gigabytes up front.
        for (std::uint64_t have = 0; have < body;) {
            const std::size_t step = static_cast<std::size_t>(std::min<std::uint64_t>(body - have, 1u << 20));
            p.bytes.resize(static_cast<std::size_t>(head + have) + step);
            read_exactly(p.bytes.data() + head + have, step, p.index, "the layers");
            have += step;
        }
    }
    points_started_ += p.chunk.points;
    ++chunks_started_;
    return true;
}

void LazDecoder::decode_pointwise_sequential() {
    // Without a table the chunk ends where its arithmetic stream ends: decode from the bytes
    // read so far, and when they run out before the chunk's last point, read more and retry.
    Pending p;
    p.index = chunks_started_;
    p.chunk.offset = stream_.position() - carry_.size();
    p.chunk.points =
        format_.chunked() ? std::min<std::uint64_t>(format_.chunk_size, point_count_ - points_started_) : point_count_;
    const std::size_t length = format_.record_length;
    bool at_end = false;
    if (!format_.chunked()) {
        // Compressor 1: one stream to the end of the input; its size bounds the point count.
        for (std::size_t got = 1; got > 0;) {
            const std::size_t had = carry_.size();
            carry_.resize(had + (1u << 20));
            got = stream_.read(carry_.data() + had, 1u << 20);
            carry_.resize(had + got);
        }
        at_end = true;
        if (!plausible_points(p.chunk.points, carry_.size()) || p.chunk.points * length > max_chunk_record_bytes)
            chunk_error(p.index, p.chunk, stream_.position(),
                        "the input ends after " + std::to_string(carry_.size()) + " compressed bytes, too few for " +
                            std::to_string(p.chunk.points) + " points (truncated file?)");
    }
    // Start from a guess (LAZ is 5-10 times smaller than LAS) and double on each retry.
    std::size_t want =
        std::clamp<std::size_t>(static_cast<std::size_t>(p.chunk.points) * length / 4, 1u << 16, 1u << 22);
    for (;;) {
        if (carry_.size() < want && !at_end) {
            const std::size_t had = carry_.size();
            carry_.resize(want);
            const std::size_t got = stream_.read(carry_.data() + had, want - had);
            carry_.resize(had + got);
            at_end = had + got < want;
        }
        p.chunk.bytes = carry_.size();
        if (decoded_.empty()) {
            // Records are allocated only once the input shows enough bytes for them.
            if (!plausible_points(p.chunk.points, carry_.size()))
                chunk_error(p.index, p.chunk, p.chunk.offset + carry_.size(),
                            "the input ends after " + std::to_string(carry_.size()) + " bytes, too few for " +
                                std::to_string(p.chunk.points) + " points (truncated or corrupt)");
            decoded_.resize_for_overwrite(static_cast<std::size_t>(p.chunk.points) * length);
        }
        try {
            const std::size_t used =
                decode_pointwise_chunk(format_, carry_, p.chunk.points, decoded_.data(), stores_.local());
            carry_.erase(carry_.begin(), carry_.begin() + static_cast<std::ptrdiff_t>(used));
            break;
        } catch (const ChunkError& e) {
            if (at_end) chunk_error(p.index, p.chunk, p.chunk.offset + e.offset, e.what());
            want = carry_.size() * 2;
        }
    }
    decoded_at_ = 0;
    points_started_ += p.chunk.points;
    ++chunks_started_;
}

void LazDecoder::decode_next_batch() {
    decoded_.clear();
    decoded_at_ = 0;
    if (!format_.layered() && !have_table_) {
        if (points_started_ < point_count_) decode_pointwise_sequential();
        return;
    }
    std::vector<Pending> batch;
    std::uint64_t points = 0;
    const std::size_t min_chunks = 2 * static_cast<std::size_t>(tbb::this_task_arena::max_concurrency());
    while ((points < batch_points || batch.size() < min_chunks) && batch.size() < 4096) {
        Pending p;
        if (!next_chunk_bytes(p)) break;
        points += p.chunk.points;
        batch.push_back(std::move(p));
    }
    if (batch.empty()) return;
    const std::size_t length = format_.record_length;
    std::vector<std::size_t> first_record(batch.size() + 1, 0);
    for (std::size_t i = 0; i < batch.size(); ++i)
        first_record[i + 1] = first_record[i] + static_cast<std::size_t>(batch[i].chunk.points);
    decoded_.resize_for_overwrite(first_record.back() * length);
    // Each chunk is independent (its models start fresh), so chunks decode in parallel; errors
    // are kept per chunk and the first one in file order is reported, whatever the timing.
    std::vector<std::optional<ChunkError>> errors(batch.size());
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, batch.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                try {
                    std::byte* out = decoded_.data() + first_record[i] * length;
                    ModelStore& store = stores_.local();
                    if (format_.layered())
                        decode_layered_chunk(format_, batch[i].bytes, batch[i].chunk.points, out, store);
                    else
                        decode_pointwise_chunk(format_, batch[i].bytes, batch[i].chunk.points, out, store);
                } catch (const ChunkError& e) {
                    errors[i] = e;
                }
            }
        });
    for (std::size_t i = 0; i < batch.size(); ++i)
        if (errors[i])
            chunk_error(batch[i].index, batch[i].chunk, batch[i].chunk.offset + errors[i]->offset, errors[i]->what());
}

std::size_t LazDecoder::read(std::byte* dst, std::size_t records) {
    const std::size_t length = format_.record_length;
    std::size_t done = 0;
    while (done < records) {
        if (decoded_at_ == decoded_.size()) {
            decode_next_batch();
            if (decoded_.empty()) break;
        }
        const std::size_t n = std::min(records - done, (decoded_.size() - decoded_at_) / length);
        std::memcpy(dst + done * length, decoded_.data() + decoded_at_, n * length);
        decoded_at_ += n * length;
        done += n;
    }
    return done;
}

} // namespace lasmesh::laz
