// SPDX-License-Identifier: Apache-2.0
// InputStream: plain read(2) for uncompressed input, a Boost.Iostreams filter chain otherwise.
#include "read/input_stream.hpp"

#include "lasmesh/error.hpp"

#include <boost/iostreams/filter/bzip2.hpp>
#include <boost/iostreams/filter/gzip.hpp>
#include <boost/iostreams/filter/lzma.hpp>
#include <boost/iostreams/filter/zstd.hpp>
#include <boost/iostreams/filtering_stream.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <limits>
#include <sys/stat.h>
#include <unistd.h>

namespace lasmesh {

namespace io = boost::iostreams;

std::string_view compression_name(Compression compression) {
    switch (compression) {
    case Compression::none: return "none";
    case Compression::gzip: return "gzip";
    case Compression::bzip2: return "bzip2";
    case Compression::xz: return "xz";
    case Compression::zstd: return "zstd";
    }
    return "unknown";
}

Compression detect_compression(const std::byte* first_bytes, std::size_t size) {
    auto starts_with = [&](std::initializer_list<unsigned> magic) {
        if (size < magic.size()) return false;
        std::size_t i = 0;
        for (unsigned byte : magic)
            if (std::to_integer<unsigned>(first_bytes[i++]) != byte) return false;
        return true;
    };
    if (starts_with({0x1f, 0x8b})) return Compression::gzip;
    if (starts_with({'B', 'Z', 'h'})) return Compression::bzip2;
    if (starts_with({0xfd, '7', 'z', 'X', 'Z', 0x00})) return Compression::xz;
    if (starts_with({0x28, 0xb5, 0x2f, 0xfd})) return Compression::zstd;
    return Compression::none;
}

namespace {
// Longest magic we look for (xz); read before choosing a decoder, then handed out again.
constexpr std::size_t sniff_size = 6;
constexpr std::streamsize filter_buffer_size = 1 << 16;
} // namespace

struct InputStream::Impl {
    std::string name;
    int fd = -1;
    bool owns_fd = false;
    Compression compression = Compression::none;
    std::array<std::byte, sniff_size> sniffed{};
    std::size_t sniffed_size = 0;
    std::size_t sniffed_used = 0;
    std::uint64_t position = 0;
    std::uint64_t raw_position = 0;
    std::optional<std::uint64_t> raw_size;
    std::unique_ptr<io::filtering_istream> decompressed;

    ~Impl() {
        decompressed.reset();
        if (owns_fd) ::close(fd);
    }

    // Bytes of the file or pipe itself: first the sniffed prefix, then read(2).
    std::size_t raw_read(std::byte* dst, std::size_t size) {
        std::size_t done = 0;
        if (sniffed_used < sniffed_size) {
            done = std::min(size, sniffed_size - sniffed_used);
            std::memcpy(dst, sniffed.data() + sniffed_used, done);
            sniffed_used += done;
        }
        while (done < size) {
            ssize_t got = ::read(fd, dst + done, size - done);
            if (got == 0) break;
            if (got < 0) {
                if (errno == EINTR) continue;
                throw_input_error(name, "read error after " + std::to_string(raw_position + done) +
                                            " bytes: " + std::strerror(errno));
            }
            done += static_cast<std::size_t>(got);
        }
        raw_position += done;
        return done;
    }

    // Boost.Iostreams source over the raw bytes, so decompressors pull from raw_read().
    struct RawSource {
        using char_type = char;
        using category = io::source_tag;
        Impl* impl;
        std::streamsize read(char* dst, std::streamsize size) {
            std::size_t got = impl->raw_read(reinterpret_cast<std::byte*>(dst), static_cast<std::size_t>(size));
            return got == 0 ? -1 : static_cast<std::streamsize>(got);
        }
    };
};

namespace {
// Boost's messages ("gzip error: iostream error") hide the cause; name it where we can.
std::string decoder_message(const std::exception& e) {
    if (auto* gzip = dynamic_cast<const io::gzip_error*>(&e)) {
        switch (gzip->error()) {
        case io::gzip::bad_crc: return "CRC mismatch, the data is damaged";
        case io::gzip::bad_length: return "length mismatch in the gzip trailer";
        case io::gzip::bad_header: return "bad gzip member header";
        case io::gzip::bad_footer: return "gzip trailer missing or damaged (truncated?)";
        case io::gzip::zlib_error:
            // Z_BUF_ERROR (-5) at the end of input: the deflate data stops mid-stream.
            return gzip->zlib_error_code() == -5
                       ? "the compressed data ends early"
                       : "deflate data damaged (zlib error " + std::to_string(gzip->zlib_error_code()) + ")";
        default: break;
        }
    }
    return e.what();
}

void push_decompressor(io::filtering_istream& chain, Compression compression) {
    switch (compression) {
    case Compression::gzip: chain.push(io::gzip_decompressor(), filter_buffer_size); break;
    case Compression::bzip2: chain.push(io::bzip2_decompressor(), filter_buffer_size); break;
    case Compression::xz: chain.push(io::lzma_decompressor(), filter_buffer_size); break;
    case Compression::zstd: chain.push(io::zstd_decompressor(), filter_buffer_size); break;
    case Compression::none: break;
    }
}
} // namespace

InputStream::InputStream(const std::string& path) : impl_(std::make_unique<Impl>()) {
    Impl& s = *impl_;
    if (path == "-") {
        s.name = "standard input";
        s.fd = STDIN_FILENO;
        // Waiting for binary LAS from the keyboard looks like a hang: say what was meant instead.
        if (::isatty(s.fd))
            throw Error(ErrorKind::usage, "reading a LAS stream from a terminal: pipe a file into `-` "
                                          "(e.g. cat deck.las | lasmesh - ...) or give its path");
    } else {
        s.name = path;
        s.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (s.fd < 0) throw_input_error(path, std::string("cannot open: ") + std::strerror(errno));
        s.owns_fd = true;
    }
    struct stat info {};
    if (::fstat(s.fd, &info) == 0) {
        if (S_ISDIR(info.st_mode)) throw_input_error(s.name, "is a directory, expected a LAS file");
        if (S_ISREG(info.st_mode)) {
            s.raw_size = static_cast<std::uint64_t>(info.st_size);
            // We read front to back once: tell the kernel to read ahead aggressively.
            ::posix_fadvise(s.fd, 0, 0, POSIX_FADV_SEQUENTIAL);
        }
    }

    s.sniffed_size = s.raw_read(s.sniffed.data(), s.sniffed.size());
    s.raw_position = 0;
    s.compression = detect_compression(s.sniffed.data(), s.sniffed_size);
    if (s.compression != Compression::none) {
        s.decompressed = std::make_unique<io::filtering_istream>();
        push_decompressor(*s.decompressed, s.compression);
        s.decompressed->push(Impl::RawSource{&s}, filter_buffer_size);
        // Let decoder exceptions through instead of a silent end of stream.
        s.decompressed->exceptions(std::ios::badbit);
    }
}

InputStream::~InputStream() = default;

std::size_t InputStream::read(std::byte* dst, std::size_t size) {
    Impl& s = *impl_;
    std::size_t got = 0;
    if (!s.decompressed) {
        got = s.raw_read(dst, size);
    } else {
        try {
            std::istream& in = *s.decompressed;
            if (in) {
                in.read(reinterpret_cast<char*>(dst), static_cast<std::streamsize>(size));
                got = static_cast<std::size_t>(in.gcount());
            }
        } catch (const Error&) {
            throw;
        } catch (const std::exception& e) {
            throw_input_error(s.name, "corrupt or truncated " + std::string(compression_name(s.compression)) +
                                          " stream near compressed byte " + std::to_string(s.raw_position) + ": " +
                                          decoder_message(e));
        }
    }
    s.position += got;
    return got;
}

std::uint64_t InputStream::skip(std::uint64_t size) {
    Impl& s = *impl_;
    // A regular uncompressed file seeks past: a tile that reads a few of a COPC file's chunks
    // reads only those.
    if (!s.decompressed && s.raw_size && s.sniffed_used == s.sniffed_size && size >= (1u << 16)) {
        const std::uint64_t step = std::min(size, *s.raw_size - std::min(*s.raw_size, s.raw_position));
        if (::lseek(s.fd, static_cast<off_t>(step), SEEK_CUR) >= 0) {
            s.raw_position += step, s.position += step;
            return step;
        }
    }
    std::array<std::byte, 1 << 14> scratch;
    std::uint64_t done = 0;
    while (done < size) {
        std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(scratch.size(), size - done));
        std::size_t got = read(scratch.data(), want);
        done += got;
        if (got < want) break;
    }
    return done;
}

std::uint64_t InputStream::drain() {
    Impl& s = *impl_;
    // A regular uncompressed file needs no reading: its size says what is left.
    if (!s.decompressed && s.raw_size && *s.raw_size >= s.raw_position) {
        const std::uint64_t rest = *s.raw_size - s.raw_position;
        s.raw_position += rest, s.position += rest;
        return rest;
    }
    return skip(std::numeric_limits<std::uint64_t>::max());
}

const std::string& InputStream::name() const {
    return impl_->name;
}
Compression InputStream::compression() const {
    return impl_->compression;
}
std::uint64_t InputStream::position() const {
    return impl_->position;
}
std::uint64_t InputStream::raw_position() const {
    return impl_->raw_position;
}
std::optional<std::uint64_t> InputStream::raw_size() const {
    return impl_->raw_size;
}

} // namespace lasmesh
