// SPDX-License-Identifier: Apache-2.0
#include "grid/tile_cells.hpp"

#include "byte_order.hpp"
#include "io/output_file.hpp"
#include "lasmesh/error.hpp"

#include <array>
#include <bit>
#include <cstring>
#include <fstream>

namespace lasmesh {

namespace {

constexpr char magic[9] = "LMTILE02";
constexpr std::uint64_t fnv_start = 0xcbf29ce484222325ULL, fnv_prime = 0x100000001b3ULL;

void hash_into(std::uint64_t& hash, const std::byte* data, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) hash = (hash ^ static_cast<std::uint8_t>(data[i])) * fnv_prime;
}

// Words into the OutputFile through a buffer, hashed on the way.
class WordWriter {
  public:
    explicit WordWriter(OutputFile& file) : file_(file) {}
    void bytes(const void* data, std::size_t size) {
        const auto* at = static_cast<const std::byte*>(data);
        hash_into(hash_, at, size);
        buffer_.insert(buffer_.end(), at, at + size);
        if (buffer_.size() >= (1u << 20)) flush();
    }
    void word(std::uint64_t value) {
        std::array<std::byte, 8> le;
        store_le<std::uint64_t>(le.data(), value);
        bytes(le.data(), le.size());
    }
    void text(const std::string& s) {
        word(s.size());
        bytes(s.data(), s.size());
    }
    void finish() {
        word(hash_); // the hash of every byte before it
        flush();
    }

  private:
    void flush() {
        file_.write(buffer_.data(), buffer_.size());
        buffer_.clear();
    }
    OutputFile& file_;
    std::vector<std::byte> buffer_;
    std::uint64_t hash_ = fnv_start;
};

// Words out of a file read whole, hashed on the way; every shortfall an Error naming the file.
class WordReader {
  public:
    WordReader(std::vector<std::byte> bytes, std::string path) : bytes_(std::move(bytes)), path_(std::move(path)) {}
    std::uint64_t word() {
        need(8, "a number");
        const std::uint64_t value = load_le<std::uint64_t>(bytes_.data() + at_);
        hash_into(hash_, bytes_.data() + at_, 8);
        at_ += 8;
        return value;
    }
    std::string text() {
        const std::uint64_t size = count(1, "text");
        std::string s(reinterpret_cast<const char*>(bytes_.data() + at_), size);
        hash_into(hash_, bytes_.data() + at_, size);
        at_ += size;
        return s;
    }
    // A count of items of `item_bytes` each, checked against the bytes left.
    std::uint64_t count(std::uint64_t item_bytes, const std::string& what) {
        const std::uint64_t n = word();
        if (n > (bytes_.size() - at_) / item_bytes)
            fail("at byte " + std::to_string(at_ - 8) + ": " + std::to_string(n) + " " + what +
                 " promised, more than the file holds (cut short or damaged)");
        return n;
    }
    void check_hash() {
        const std::uint64_t expected = hash_;
        need(8, "the hash");
        const std::uint64_t stored = load_le<std::uint64_t>(bytes_.data() + at_);
        at_ += 8;
        if (stored != expected) fail("damaged: its hash does not match its contents");
        if (at_ != bytes_.size())
            fail(std::to_string(bytes_.size() - at_) + " bytes after the end of a tile's file (damaged)");
    }
    [[noreturn]] void fail(const std::string& what) const { throw_input_error(path_, what); }

  private:
    void need(std::size_t size, const std::string& what) const {
        if (bytes_.size() - at_ < size) fail("cut short at byte " + std::to_string(at_) + ": " + what + " expected");
    }
    std::vector<std::byte> bytes_;
    std::string path_;
    std::size_t at_ = 0;
    std::uint64_t hash_ = fnv_start;
};

// Words read from a file as they are needed (a part of a tile's file), not hashed; every
// shortfall an Error naming the file.
class PartReader {
  public:
    explicit PartReader(const std::string& path) : in_(path, std::ios::binary | std::ios::ate), path_(path) {
        if (!in_) throw_input_error(path, "missing: this tile has not been written (or cannot be opened)");
        size_ = static_cast<std::uint64_t>(in_.tellg());
        in_.seekg(0);
    }
    std::vector<std::byte> bytes(std::uint64_t size, const std::string& what) {
        if (size_ - at_ < size) fail("cut short at byte " + std::to_string(at_) + ": " + what + " expected");
        std::vector<std::byte> read(size);
        in_.read(reinterpret_cast<char*>(read.data()), static_cast<std::streamsize>(size));
        if (!in_) fail("cannot be read");
        at_ += size;
        return read;
    }
    std::uint64_t word() { return load_le<std::uint64_t>(bytes(8, "a number").data()); }
    void skip_text() { skip(word(), "text"); }
    // A count of items of `item_bytes` each, checked against the bytes left.
    std::uint64_t count(std::uint64_t item_bytes, const std::string& what) {
        const std::uint64_t n = word();
        if (n > (size_ - at_) / item_bytes)
            fail("at byte " + std::to_string(at_ - 8) + ": " + std::to_string(n) + " " + what +
                 " promised, more than the file holds (cut short or damaged)");
        return n;
    }
    void skip(std::uint64_t size, const std::string& what) {
        if (size_ - at_ < size) fail("cut short at byte " + std::to_string(at_) + ": " + what + " expected");
        at_ += size;
        in_.seekg(static_cast<std::streamoff>(at_));
    }
    std::uint64_t at() const { return at_; }
    [[noreturn]] void fail(const std::string& what) const { throw_input_error(path_, what); }

  private:
    std::ifstream in_;
    std::string path_;
    std::uint64_t size_ = 0, at_ = 0;
};

void read_cell(const std::byte* at, CellSums& cell) {
    const auto next = [&] {
        const std::uint64_t value = load_le<std::uint64_t>(at);
        at += 8;
        return value;
    };
    cell.count = next();
    for (std::uint64_t& p : cell.position) p = next();
    for (std::uint64_t& c : cell.color) c = next();
    for (std::uint64_t& m : cell.moments) m = next();
}

} // namespace

std::uint64_t write_tile_cells(const TileCells& tile, const std::string& path, const CellGrid* grid) {
    OutputFile file(path);
    WordWriter out(file);
    out.bytes(magic, 8);
    out.word(tile.plan_hash);
    out.word(tile.index);
    out.word(tile.color ? 1 : 0);
    out.word(tile.color_max_word);
    out.text(tile.device);
    out.word(tile.inputs.size());
    for (const TileInputCount& input : tile.inputs)
        out.word(input.input), out.word(input.records), out.word(input.outside);
    out.word(tile.warnings.size());
    for (const TileWarning& warning : tile.warnings) out.word(warning.input), out.text(warning.text);
    const auto cell = [&](const CellSums& c) {
        out.word(c.count);
        for (const std::uint64_t p : c.position) out.word(p);
        for (const std::uint64_t v : c.color) out.word(v);
        for (const std::uint64_t m : c.moments) out.word(m);
    };
    if (grid) { // the grid's bricks, their cells one brick after the other in key order
        out.word(grid->brick_keys.size());
        std::uint64_t first = 0;
        for (std::size_t b = 0; b < grid->brick_keys.size(); ++b) {
            out.word(grid->brick_keys[b]), out.word(grid->brick_masks[b]), out.word(first);
            first += static_cast<std::uint64_t>(std::popcount(grid->brick_masks[b]));
        }
        out.word(first);
        for (std::size_t b = 0; b < grid->brick_keys.size(); ++b) {
            const auto n = static_cast<std::uint64_t>(std::popcount(grid->brick_masks[b]));
            for (std::uint64_t c = 0; c < n; ++c) cell(grid->cells[grid->brick_first[b] + c]);
        }
    } else {
        out.word(tile.brick_keys.size());
        for (std::size_t b = 0; b < tile.brick_keys.size(); ++b)
            out.word(tile.brick_keys[b]), out.word(tile.brick_masks[b]), out.word(tile.brick_first[b]);
        out.word(tile.cells.size());
        for (const CellSums& c : tile.cells) cell(c);
    }
    out.finish();
    file.commit();
    return file.bytes();
}

TileCells read_tile_cells(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw_input_error(path, "missing: this tile has not been written (or cannot be opened)");
    std::vector<std::byte> bytes(static_cast<std::size_t>(in.tellg()));
    in.seekg(0);
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!in) throw_input_error(path, "cannot be read");
    if (bytes.size() < 8 || std::memcmp(bytes.data(), magic, 8) != 0)
        throw_input_error(path, "not a lasmesh tile's cell sums (bytes 0-7 are not \"LMTILE02\")");
    WordReader read(std::move(bytes), path);
    TileCells tile;
    // The magic's bytes count in the hash: read them as a word (its value is not needed).
    (void)read.word();
    tile.plan_hash = read.word();
    tile.index = read.word();
    const std::uint64_t color = read.word();
    const std::uint64_t max_word = read.word();
    if (color > 1 || max_word > 65535) read.fail("damaged: its colour fields are out of range");
    tile.color = color == 1;
    tile.color_max_word = static_cast<std::uint32_t>(max_word);
    tile.device = read.text();
    tile.inputs.resize(read.count(24, "inputs"));
    for (TileInputCount& input : tile.inputs) {
        input.input = read.word(), input.records = read.word(), input.outside = read.word();
        if (input.outside > input.records) read.fail("damaged: more points outside the grid than read");
    }
    tile.warnings.resize(read.count(16, "warnings"));
    for (TileWarning& warning : tile.warnings) warning.input = read.word(), warning.text = read.text();
    const std::uint64_t bricks = read.count(24, "bricks");
    tile.brick_keys.resize(bricks), tile.brick_masks.resize(bricks), tile.brick_first.resize(bricks);
    for (std::size_t b = 0; b < bricks; ++b)
        tile.brick_keys[b] = read.word(), tile.brick_masks[b] = read.word(), tile.brick_first[b] = read.word();
    tile.cells.resize(read.count(104, "cells"));
    for (CellSums& cell : tile.cells) {
        cell.count = read.word();
        for (std::uint64_t& p : cell.position) p = read.word();
        for (std::uint64_t& c : cell.color) c = read.word();
        for (std::uint64_t& m : cell.moments) m = read.word();
    }
    read.check_hash();
    // What merge relies on: keys ascending, each brick's cells inside the cells, in order.
    std::uint64_t next = 0;
    for (std::size_t b = 0; b < bricks; ++b) {
        if (b > 0 && tile.brick_keys[b] <= tile.brick_keys[b - 1]) read.fail("damaged: its bricks are not in order");
        const auto n = static_cast<std::uint64_t>(std::popcount(tile.brick_masks[b]));
        if (n == 0 || tile.brick_first[b] != next)
            read.fail("damaged: brick " + std::to_string(b) + "'s cells do not follow");
        next += n;
    }
    if (next != tile.cells.size())
        read.fail("damaged: its bricks hold " + std::to_string(next) + " cells, its list " +
                  std::to_string(tile.cells.size()));
    return tile;
}

TileCells read_tile_bricks(const std::string& path, const std::function<bool(std::uint64_t key)>& wanted) {
    PartReader read(path);
    if (read.bytes(8, "the magic") != std::vector<std::byte>(reinterpret_cast<const std::byte*>(magic),
                                                             reinterpret_cast<const std::byte*>(magic) + 8))
        read.fail("not a lasmesh tile's cell sums (bytes 0-7 are not \"LMTILE02\")");
    TileCells tile;
    tile.plan_hash = read.word();
    tile.index = read.word();
    tile.color = read.word() == 1;
    tile.color_max_word = static_cast<std::uint32_t>(read.word());
    read.skip_text(); // the device
    read.skip(24 * read.count(24, "inputs"), "inputs");
    for (std::uint64_t w = read.count(16, "warnings"); w > 0; --w) (void)read.word(), read.skip_text();
    const std::uint64_t bricks = read.count(24, "bricks");
    const std::vector<std::byte> table = read.bytes(24 * bricks, "bricks");
    const std::uint64_t cells = read.count(104, "cells"), cells_at = read.at();
    // The wanted bricks' cells, each run of them one read.
    std::uint64_t next = 0;
    for (std::size_t b = 0; b < bricks;) {
        const std::byte* entry = table.data() + 24 * b;
        const std::uint64_t key = load_le<std::uint64_t>(entry), mask = load_le<std::uint64_t>(entry + 8);
        if (!wanted(key)) {
            next += static_cast<std::uint64_t>(std::popcount(mask)), ++b;
            continue;
        }
        const std::uint64_t run_first = next;
        for (; b < bricks; ++b) {
            const std::byte* e = table.data() + 24 * b;
            const std::uint64_t k = load_le<std::uint64_t>(e), m = load_le<std::uint64_t>(e + 8);
            if (!wanted(k)) break;
            const auto n = static_cast<std::uint64_t>(std::popcount(m));
            if ((!tile.brick_keys.empty() && k <= tile.brick_keys.back()) || n == 0 ||
                load_le<std::uint64_t>(e + 16) != next || next + n > cells)
                read.fail("damaged: brick " + std::to_string(b) + "'s cells do not follow");
            tile.brick_keys.push_back(k), tile.brick_masks.push_back(m), tile.brick_first.push_back(tile.cells.size());
            tile.cells.resize(tile.cells.size() + n);
            next += n;
        }
        read.skip(cells_at + 104 * run_first - read.at(), "cells");
        const std::vector<std::byte> run = read.bytes(104 * (next - run_first), "cells");
        CellSums* to = tile.cells.data() + tile.cells.size() - (next - run_first);
        for (std::uint64_t c = 0; c < next - run_first; ++c) read_cell(run.data() + 104 * c, to[c]);
    }
    return tile;
}

} // namespace lasmesh
