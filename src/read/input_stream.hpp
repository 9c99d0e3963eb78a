// SPDX-License-Identifier: Apache-2.0
// A forward-only byte stream over a file or standard input, decompressed on the fly when its
// first bytes carry a gzip, bzip2, xz or zstd signature. It never seeks backwards, so pipes work as
// well as files; plain input is read with large read(2) calls straight into the caller's buffer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace lasmesh {

enum class Compression { none, gzip, bzip2, xz, zstd };

std::string_view compression_name(Compression compression);

// Recognises a compressed stream by its magic bytes (never by the file name).
Compression detect_compression(const std::byte* first_bytes, std::size_t size);

class InputStream {
  public:
    // `path` is a file path, or "-" for standard input. Throws Error (input) when the path is
    // missing, a directory or unreadable; Error (usage) for "-" when standard input is a terminal.
    explicit InputStream(const std::string& path);
    ~InputStream();
    InputStream(const InputStream&) = delete;
    InputStream& operator=(const InputStream&) = delete;

    // Reads up to `size` bytes into `dst`; returns fewer only at the end of the stream.
    // Throws Error (input) on a read error or a corrupt compressed stream.
    std::size_t read(std::byte* dst, std::size_t size);

    // Reads and discards `size` bytes (seeks past them in a regular uncompressed file); returns how
    // many there were before the end.
    std::uint64_t skip(std::uint64_t size);
    // Reads to the end and returns how many bytes there were. For compressed input this runs the
    // decoder to its end, so its end-of-stream checks (gzip CRC and length, ...) are made: a
    // stream read only up to what the header promises would otherwise never be verified.
    std::uint64_t drain();

    // "standard input" or the path, for messages.
    const std::string& name() const;
    Compression compression() const;
    // Bytes of the (decompressed) stream handed out so far: the byte offset of the next read.
    std::uint64_t position() const;
    // Bytes taken from the file or pipe itself (compressed bytes for compressed input).
    std::uint64_t raw_position() const;
    // Size of the underlying file when it is a regular file; none for pipes.
    std::optional<std::uint64_t> raw_size() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace lasmesh
