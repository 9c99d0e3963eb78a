// SPDX-License-Identifier: Apache-2.0
// The adaptive range decoder LASzip entropy-codes with (Isenburg 2013, "LASzip: lossless
// compression of LiDAR data", section 3; the coder is A. Said's FastAC, "Introduction to
// arithmetic coding", 2003), with its adaptive bit and symbol models and the integer
// decoder that codes corrections to a prediction as (bucket k, offset in bucket).
// Written from those descriptions; every constant below is part of the LAZ format.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace lasmesh::laz {

constexpr std::uint32_t bit_length_shift = 13;    // bit model probabilities are 13-bit
constexpr std::uint32_t bit_max_count = 1u << 13; // halve the counts beyond this
constexpr std::uint32_t sym_length_shift = 15;    // symbol distributions are 15-bit
constexpr std::uint32_t sym_max_count = 1u << 15;
constexpr std::uint32_t min_length = 1u << 24; // renormalize below this interval length

class ModelStore;
struct ModelSize;

// Adaptive binary model: probability of a 0 in 13 bits, refreshed on a growing cycle.
struct BitModel {
    std::uint32_t bit_0_count = 1;
    std::uint32_t bit_count = 2;
    std::uint32_t bit_0_prob = 1u << 12;
    std::uint32_t update_cycle = 4;
    std::uint32_t bits_until_update = 4;
    void update();
};

// Adaptive model over `symbols` symbols: cumulative distribution in 15 bits, plus a lookup
// table from the top bits of a scaled value to the first symbol it can belong to. The table
// is the decoder's own search aid (finer than the one the format's description suggests, so
// that most look-ups land on one or two candidate symbols); only the distribution and counts
// are defined by the format.
// Distribution, table and counts share one allocation, in 16-bit entries: the distribution is
// below 2^15, symbols number at most 516, and a count stays below 2^15 plus twice the longest
// update cycle (8 * (516 + 6)), under 2^16. Half the bytes of 32-bit entries: the models a
// format-3 point touches (up to 3 KB each for 256 symbols, dozens of them) overflowed the 48 KB
// L1 cache about 3 times per point (cachegrind).
class SymbolModel {
  public:
    // A fresh model of `symbols` symbols, its memory from `store` and given back there.
    SymbolModel(std::uint32_t symbols, ModelStore& store);
    SymbolModel(SymbolModel&&) noexcept = default; // the block moves, the pointers stay valid
    SymbolModel& operator=(SymbolModel&&) noexcept = default;
    ~SymbolModel();
    void update();

    const std::uint16_t* distribution = nullptr; // symbols + 2 entries; the last two are
                                                 // sentinels (0xFFFF) no scaled value reaches
    const std::uint16_t* table = nullptr;        // table_last + 2 entries
    std::uint16_t* counts = nullptr;
    std::uint32_t table_shift = 0;
    std::uint32_t table_last = 0; // largest table index a (corrupt) value may use
    std::uint32_t last_symbol = 0;
    std::uint32_t likely = 0; // the symbol with the largest count (0 with an empty interval
                              // when that is under 40% likely: see update())
    // d[likely] and d[likely + 1], kept beside it: the first guess then needs no load that
    // depends on another (model -> distribution -> entry), which put 4-5 cycles on every symbol.
    std::uint32_t likely_low = 0, likely_high = 0;
    std::uint32_t symbols_until_update = 0;
    std::uint32_t symbols = 0;
    std::uint32_t total_count = 0;
    std::uint32_t update_cycle = 0;

  private:
    friend class ModelStore;
    struct Fresh {};
    SymbolModel(std::uint32_t symbols, Fresh); // builds it
    std::size_t storage_size() const { return 2 * std::size_t{symbols} + 2 + table_last + 2; }
    std::unique_ptr<std::uint16_t[]> storage_;
    ModelSize* home_ = nullptr; // where storage_ goes back (none for a store's own fresh models)
};

// A ModelStore's fresh model of one size, and the memory of dropped models of that size.
struct ModelSize {
    SymbolModel fresh;
    std::vector<std::unique_ptr<std::uint16_t[]>> spare;
};

// Where the symbol models of one thread's chunks come from. Every chunk starts its models afresh,
// and a COPC node holds only a few points, so making models is most of its work: the store builds
// a fresh model of each size once and copies it, and hands a dropped model's memory to the next
// model of its size (malloc and free were a quarter of COPC's profile). Owned by whoever decodes
// chunks on a thread, one after another; it outlives their models.
class ModelStore {
  public:
    ModelStore() = default;
    ModelStore(const ModelStore&) = delete;
    ModelStore& operator=(const ModelStore&) = delete;

    // The fresh model and the spare memory for models of `symbols` symbols (made on first use).
    ModelSize& size(std::uint32_t symbols);

  private:
    std::deque<ModelSize> sizes_;        // a dozen or so (the item decoders' constants); they stay in place
    std::vector<ModelSize*> by_symbols_; // index: the number of symbols
};

// A SymbolModel built on first use: a chunk of a few points (COPC nodes) would otherwise spend
// its time building models for values that never occur in it.
class LazySymbolModel {
  public:
    explicit LazySymbolModel(std::uint32_t symbols) : symbols_(symbols) {}
    SymbolModel& get(ModelStore& store) {
        if (!model_) model_ = std::make_unique<SymbolModel>(symbols_, store);
        return *model_;
    }

  private:
    std::uint32_t symbols_;
    std::unique_ptr<SymbolModel> model_;
};

// Range decoder over one buffer. Reading past its end yields zeros and is counted, so a
// truncated or corrupt stream decodes to garbage values but never reads out of bounds; the
// caller checks overrun() once per chunk or layer. Small and copyable: a hot function copies
// it into a local so that its state stays in registers, and copies it back at the end. So its
// steps are forced inline: one call left out of line takes the local's address and puts it back
// in memory (GCC did that to renormalize, decode_bit and read_bits in the unity build: format 3
// decoded 15% slower).
class ArithmeticDecoder {
  public:
    ArithmeticDecoder() = default;
    // A decoder with nothing to decode (an absent layer), its models made in `store`.
    explicit ArithmeticDecoder(ModelStore& store) : store_(&store) {}
    // Starts decoding at the first byte of `bytes` (reads 4 bytes of state); the models it
    // decodes with are made in `store`.
    ArithmeticDecoder(std::span<const std::byte> bytes, ModelStore& store);

    std::uint32_t decode_bit(BitModel& model);
    std::uint32_t decode_symbol(SymbolModel& model);
    std::uint32_t decode_symbol(LazySymbolModel& model) { return decode_symbol(model.get(*store_)); }
    ModelStore& store() const { return *store_; }
    std::uint32_t read_bits(std::uint32_t bits); // 1 to 32 raw bits
    std::uint32_t read_int() { return read_bits(32); }

    // Bytes consumed so far (including those read past the end).
    std::size_t position() const { return pos_; }
    bool overrun() const { return pos_ > size_; }

  private:
    std::uint32_t next_byte() {
        std::uint32_t b = pos_ < size_ ? std::to_integer<std::uint32_t>(data_[pos_]) : 0u;
        ++pos_;
        return b;
    }
    // After each decode the interval length must be at least 2^24 again. Usually one byte is
    // due or none, a coin flip a branch would mispredict: that byte is shifted in without a
    // branch, and the rare second or third byte (a symbol of probability under 2^-8) by a loop.
    [[gnu::always_inline]] void renormalize() {
        const std::uint32_t due = length_ < min_length ? 1u : 0u;
        const std::uint32_t byte = pos_ < size_ ? std::to_integer<std::uint32_t>(data_[pos_]) : 0u;
        const std::uint32_t shift = 8 * due;
        value_ = (value_ << shift) | (byte & (0u - due));
        length_ <<= shift;
        pos_ += due;
        while (length_ < min_length) {
            value_ = (value_ << 8) | next_byte();
            length_ <<= 8;
        }
    }
    std::uint32_t read_short_bits(std::uint32_t bits); // up to 19 bits at once
    static std::uint32_t search(const std::uint16_t* d, std::uint32_t dv, std::uint32_t s, std::uint32_t n);

    const std::byte* data_ = nullptr;
    ModelStore* store_ = nullptr;
    std::size_t size_ = 0;
    std::size_t pos_ = 0;
    std::uint32_t value_ = 0;
    std::uint32_t length_ = 0xFFFFFFFFu;
};

// Decodes integers coded as a correction to a prediction (Isenburg 2013, section 3.2): the
// correction's bit length k with a symbol model per context, then its value within the
// 2^(k-1)-wide bucket (low bits raw above `bits_high`). `bits` is the width of the values.
class IntegerDecoder {
  public:
    IntegerDecoder(std::uint32_t bits = 16, std::uint32_t contexts = 1, std::uint32_t bits_high = 8);
    std::int32_t decode(ArithmeticDecoder& dec, std::int32_t prediction, std::uint32_t context = 0);
    // The bit length of the last correction: later fields use it as context.
    std::uint32_t k() const { return k_; }

  private:
    std::int32_t read_corrector(ArithmeticDecoder& dec, SymbolModel& bits_model);

    std::uint32_t corr_bits_;
    std::uint32_t bits_high_;
    std::uint32_t corr_range_;
    std::int32_t corr_min_;
    std::uint32_t k_ = 0;
    // Models are made on first use: most contexts and bit lengths never occur in a chunk, and
    // small chunks (COPC nodes) would otherwise spend their time building them. They are held in
    // place, not behind a pointer: one allocation less per model (COPC +10%), and no pointer to
    // load before a model chosen by the symbol just decoded (the bit length k, or X's k as Y's
    // context); large chunks showed no change from that.
    SymbolModel& bits_model(std::uint32_t context, ModelStore& store);
    SymbolModel& corrector(std::uint32_t k, ModelStore& store);
    std::vector<std::optional<SymbolModel>> bits_models_; // one per context
    BitModel corrector0_;
    std::vector<std::optional<SymbolModel>> correctors_; // index k-1 for k = 1..corr_bits
};

// Streaming median of the last five values: the predictor of X and Y differences.
struct Median5 {
    std::int32_t v[5] = {0, 0, 0, 0, 0};
    bool high = true;
    std::int32_t get() const { return v[2]; }
    void add(std::int32_t x);
};

// Inline, like the decoder below: called twice per point.
inline void Median5::add(std::int32_t x) {
    // Five sorted values; alternately drop the largest or the smallest, so the middle one
    // follows the recent values.
    if (high) {
        if (x < v[2]) {
            v[4] = v[3];
            v[3] = v[2];
            if (x < v[0]) {
                v[2] = v[1];
                v[1] = v[0];
                v[0] = x;
            } else if (x < v[1]) {
                v[2] = v[1];
                v[1] = x;
            } else {
                v[2] = x;
            }
        } else {
            if (x < v[3]) {
                v[4] = v[3];
                v[3] = x;
            } else {
                v[4] = x;
            }
            high = false;
        }
    } else {
        if (v[2] < x) {
            v[0] = v[1];
            v[1] = v[2];
            if (v[4] < x) {
                v[2] = v[3];
                v[3] = v[4];
                v[4] = x;
            } else if (v[3] < x) {
                v[2] = v[3];
                v[3] = x;
            } else {
                v[2] = x;
            }
        } else {
            if (v[1] < x) {
                v[0] = v[1];
                v[1] = x;
            } else {
                v[0] = x;
            }
            high = true;
        }
    }
}

// The per-value functions are inline: the item decoders call them a dozen times per point.

inline SymbolModel& IntegerDecoder::bits_model(std::uint32_t context, ModelStore& store) {
    auto& m = bits_models_[context];
    if (!m) m.emplace(corr_bits_ + 1, store);
    return *m;
}

inline SymbolModel& IntegerDecoder::corrector(std::uint32_t k, ModelStore& store) {
    auto& m = correctors_[k - 1];
    if (!m) m.emplace(k <= bits_high_ ? 1u << k : 1u << bits_high_, store);
    return *m;
}

[[gnu::always_inline]] inline std::uint32_t ArithmeticDecoder::decode_bit(BitModel& m) {
    // 0 below x, 1 above; selected without a branch.
    const std::uint32_t x = m.bit_0_prob * (length_ >> bit_length_shift);
    const std::uint32_t bit = value_ >= x ? 1u : 0u;
    const std::uint32_t mask = 0u - bit;
    value_ -= x & mask;
    length_ = (x & ~mask) | ((length_ - x) & mask);
    m.bit_0_count += bit ^ 1u;
    renormalize();
    if (--m.bits_until_update == 0) m.update();
    return bit;
}

inline std::uint32_t ArithmeticDecoder::search(const std::uint16_t* d, std::uint32_t dv, std::uint32_t s,
                                               std::uint32_t n) {
    while (n > s + 1) {
        const std::uint32_t k = (s + n) >> 1;
        if (d[k] > dv)
            n = k;
        else
            s = k;
    }
    return s;
}

[[gnu::always_inline]] inline std::uint32_t ArithmeticDecoder::decode_symbol(SymbolModel& m) {
    // The symbol s is the one with d[s] * unit <= value < d[s + 1] * unit (d: the distribution,
    // unit: the interval length / 2^15; the last symbol's interval ends at the length).
    const std::uint32_t unit = length_ >> sym_length_shift;
    const std::uint16_t* d = m.distribution;
    // First the model's most frequent symbol: two products and a compare, no division. The
    // branch mostly goes the same way for a skewed model and the decoding runs ahead on it.
    const std::uint32_t g = m.likely;
    std::uint32_t s = g;
    std::uint32_t x = m.likely_low * unit;
    std::uint32_t y = g == m.last_symbol ? length_ : m.likely_high * unit;
    if (value_ - x >= y - x) {
        // One division gives the quotient; comparing it with d[k] decides exactly what
        // comparing value with unit * d[k] would (no product overflows 32 bits).
        // Below 2^15 + 2^15 / unit as value < length; above 2^15 (the last symbol's, as
        // d[last] < 2^15) it is cut to 2^15, and only corrupt input goes further: so the table
        // index stays within the table and no sentinel (0xFFFF) is ever reached.
        std::uint32_t dv = value_ / unit;
        dv = dv < (1u << sym_length_shift) ? dv : 1u << sym_length_shift;
        const std::uint32_t t = dv >> m.table_shift;
        // The table bounds s to [table[t], table[t + 1]]: mostly one or two candidates, decided
        // without a branch (their bounds loaded at once); a wider range (a bucket with several
        // rare symbols) is searched.
        s = m.table[t];
        const std::uint32_t n = m.table[t + 1] + 1;
        std::uint32_t low, high; // d[s], d[s + 1]
        if (n > s + 2) {
            s = search(d, dv, s, n);
            low = d[s];
            high = d[s + 1];
        } else {
            const std::uint32_t d0 = d[s], d1 = d[s + 1], d2 = d[s + 2]; // d[symbols + 1]: sentinel too
            const bool up = d1 <= dv;
            s += up ? 1u : 0u;
            low = up ? d1 : d0;
            high = up ? d2 : d1;
        }
        x = low * unit;
        y = s == m.last_symbol ? length_ : high * unit; // high: a sentinel for the last
    }
    value_ -= x;
    length_ = y - x;
    renormalize();
    ++m.counts[s];
    if (--m.symbols_until_update == 0) m.update();
    return s;
}

[[gnu::always_inline]] inline std::uint32_t ArithmeticDecoder::read_short_bits(std::uint32_t bits) {
    length_ >>= bits;
    std::uint32_t sym = value_ / length_;
    value_ -= length_ * sym;
    renormalize();
    return sym;
}

[[gnu::always_inline]] inline std::uint32_t ArithmeticDecoder::read_bits(std::uint32_t bits) {
    // More than 19 bits are sent as a low 16-bit part, then the rest (at most 16 bits). Written
    // without recursion so that it inlines: a call that takes the decoder's address would keep
    // the caller's local copy of the decoder in memory instead of registers.
    if (bits > 19) {
        const std::uint32_t low = read_short_bits(16);
        return (read_short_bits(bits - 16) << 16) | low;
    }
    return read_short_bits(bits);
}

[[gnu::always_inline]] inline std::int32_t IntegerDecoder::read_corrector(ArithmeticDecoder& dec,
                                                                          SymbolModel& bits_model) {
    k_ = dec.decode_symbol(bits_model);
    if (k_ == 0) return static_cast<std::int32_t>(dec.decode_bit(corrector0_)); // 0 or 1
    if (k_ >= 32) return corr_min_;
    std::uint32_t c;
    if (k_ <= bits_high_) {
        c = dec.decode_symbol(corrector(k_, dec.store()));
    } else {
        const std::uint32_t low_bits = k_ - bits_high_;
        c = dec.decode_symbol(corrector(k_, dec.store()));
        c = (c << low_bits) | dec.read_bits(low_bits);
    }
    // Bucket k holds [-(2^k - 1), -2^(k-1)] and [2^(k-1) + 1, 2^k]: c (below 2^k) at or above
    // 2^(k-1) is c + 1, below it c + 1 - 2^k; modulo 2^32, as the int32 result wraps (k = 31).
    // The sign of a correction is a coin flip, so it is selected with a mask: GCC compiled the
    // equivalent conditional expression into a branch.
    const std::uint32_t half = 1u << (k_ - 1);
    const std::uint32_t lower = 0u - (c < half ? 1u : 0u);
    return static_cast<std::int32_t>(c + 1u - ((half << 1) & lower));
}

[[gnu::always_inline]] inline std::int32_t IntegerDecoder::decode(ArithmeticDecoder& dec, std::int32_t prediction,
                                                                  std::uint32_t context) {
    const std::int32_t corr = read_corrector(dec, bits_model(context, dec.store()));
    // Back into [0, range): below 0 add the range, at or above it subtract it (range 0 for 32-bit
    // values, which wrap by themselves). With masks: the sign of a sum is a coin flip for the
    // branch predictor.
    std::uint32_t real = static_cast<std::uint32_t>(prediction) + static_cast<std::uint32_t>(corr);
    const std::uint32_t below = 0u - (real >> 31);
    const std::uint32_t above = (0u - (real >= corr_range_ ? 1u : 0u)) & ~below;
    real += (corr_range_ & below) - (corr_range_ & above);
    return static_cast<std::int32_t>(real);
}

} // namespace lasmesh::laz
