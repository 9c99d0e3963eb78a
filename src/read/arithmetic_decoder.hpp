// The adaptive range decoder LASzip entropy-codes with (Isenburg 2013, "LASzip: lossless
// compression of LiDAR data", section 3; the coder is A. Said's FastAC, "Introduction to
// arithmetic coding", 2003), with its adaptive bit and symbol models and the integer
// decoder that codes corrections to a prediction as (bucket k, offset in bucket).
// Written from those descriptions; every constant below is part of the LAZ format.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace lasmesh::laz {

constexpr std::uint32_t bit_length_shift = 13;    // bit model probabilities are 13-bit
constexpr std::uint32_t bit_max_count = 1u << 13; // halve the counts beyond this
constexpr std::uint32_t sym_length_shift = 15;    // symbol distributions are 15-bit
constexpr std::uint32_t sym_max_count = 1u << 15;
constexpr std::uint32_t min_length = 1u << 24; // renormalize below this interval length

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
// table that narrows the search for models over more than 16 symbols.
class SymbolModel {
public:
    explicit SymbolModel(std::uint32_t symbols);
    void update();

    std::uint32_t symbols;
    std::uint32_t last_symbol;
    std::uint32_t table_shift = 0;
    std::uint32_t total_count = 0;
    std::uint32_t update_cycle;
    std::uint32_t symbols_until_update;
    std::vector<std::uint32_t> distribution;
    std::vector<std::uint32_t> counts;
    std::vector<std::uint32_t> table; // empty for small models
};

// A SymbolModel built on first use: a chunk of a few points (COPC nodes) would otherwise spend
// its time building models for values that never occur in it.
class LazySymbolModel {
public:
    explicit LazySymbolModel(std::uint32_t symbols) : symbols_(symbols) {}
    SymbolModel& get() {
        if (!model_) model_ = std::make_unique<SymbolModel>(symbols_);
        return *model_;
    }

private:
    std::uint32_t symbols_;
    std::unique_ptr<SymbolModel> model_;
};

// Range decoder over one buffer. Reading past its end yields zeros and is counted, so a
// truncated or corrupt stream decodes to garbage values but never reads out of bounds; the
// caller checks overrun() once per chunk or layer.
class ArithmeticDecoder {
public:
    ArithmeticDecoder() = default;
    // Starts decoding at the first byte of `bytes` (reads 4 bytes of state).
    explicit ArithmeticDecoder(std::span<const std::byte> bytes);

    std::uint32_t decode_bit(BitModel& model);
    std::uint32_t decode_symbol(SymbolModel& model);
    std::uint32_t decode_symbol(LazySymbolModel& model) { return decode_symbol(model.get()); }
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
    void renormalize() {
        do {
            value_ = (value_ << 8) | next_byte();
            length_ <<= 8;
        } while (length_ < (1u << 24));
    }
    std::uint32_t read_short_bits(std::uint32_t bits); // up to 19 bits at once

    const std::byte* data_ = nullptr;
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
    // small chunks (COPC nodes) would otherwise spend their time building them.
    SymbolModel& bits_model(std::uint32_t context);
    SymbolModel& corrector(std::uint32_t k);
    std::vector<std::unique_ptr<SymbolModel>> bits_models_; // one per context
    BitModel corrector0_;
    std::vector<std::unique_ptr<SymbolModel>> correctors_; // index k-1 for k = 1..corr_bits
};

// Streaming median of the last five values: the predictor of X and Y differences.
struct Median5 {
    std::int32_t v[5] = {0, 0, 0, 0, 0};
    bool high = true;
    std::int32_t get() const { return v[2]; }
    void add(std::int32_t x);
};

// The per-value functions are inline: the item decoders call them a dozen times per point.

inline SymbolModel& IntegerDecoder::bits_model(std::uint32_t context) {
    auto& m = bits_models_[context];
    if (!m) m = std::make_unique<SymbolModel>(corr_bits_ + 1);
    return *m;
}

inline SymbolModel& IntegerDecoder::corrector(std::uint32_t k) {
    auto& m = correctors_[k - 1];
    if (!m) m = std::make_unique<SymbolModel>(k <= bits_high_ ? 1u << k : 1u << bits_high_);
    return *m;
}

inline std::uint32_t ArithmeticDecoder::decode_bit(BitModel& m) {
    const std::uint32_t x = m.bit_0_prob * (length_ >> bit_length_shift);
    std::uint32_t bit;
    if (value_ < x) {
        bit = 0;
        length_ = x;
        ++m.bit_0_count;
    } else {
        bit = 1;
        value_ -= x;
        length_ -= x;
    }
    if (length_ < min_length) renormalize();
    if (--m.bits_until_update == 0) m.update();
    return bit;
}

inline std::uint32_t ArithmeticDecoder::decode_symbol(SymbolModel& m) {
    std::uint32_t x, y = length_, s;
    length_ >>= sym_length_shift;
    const std::uint32_t* d = m.distribution.data();
    if (!m.table.empty()) {
        // Interval search narrowed by the table: find s with d[s] <= value/length < d[s+1].
        std::uint32_t dv = value_ / length_;
        std::uint32_t t = dv >> m.table_shift;
        if (t >= m.table.size() - 1) t = static_cast<std::uint32_t>(m.table.size()) - 2; // corrupt input only
        s = m.table[t];
        std::uint32_t n = m.table[t + 1] + 1;
        while (n > s + 1) {
            const std::uint32_t k = (s + n) >> 1;
            if (d[k] > dv) n = k;
            else s = k;
        }
        x = d[s] * length_;
        if (s != m.last_symbol) y = d[s + 1] * length_;
    } else {
        x = s = 0;
        std::uint32_t n = m.symbols;
        std::uint32_t k = n >> 1;
        do {
            const std::uint32_t z = length_ * d[k];
            if (z > value_) {
                n = k;
                y = z;
            } else {
                s = k;
                x = z;
            }
        } while ((k = (s + n) >> 1) != s);
    }
    value_ -= x;
    length_ = y - x;
    if (length_ < min_length) renormalize();
    ++m.counts[s];
    if (--m.symbols_until_update == 0) m.update();
    return s;
}

inline std::uint32_t ArithmeticDecoder::read_short_bits(std::uint32_t bits) {
    length_ >>= bits;
    std::uint32_t sym = value_ / length_;
    value_ -= length_ * sym;
    if (length_ < min_length) renormalize();
    return sym;
}

inline std::uint32_t ArithmeticDecoder::read_bits(std::uint32_t bits) {
    // More than 19 bits are sent as a low 16-bit part, then the rest.
    if (bits > 19) {
        const std::uint32_t low = read_short_bits(16);
        return (read_bits(bits - 16) << 16) | low;
    }
    return read_short_bits(bits);
}

inline std::int32_t IntegerDecoder::read_corrector(ArithmeticDecoder& dec, SymbolModel& bits_model) {
    k_ = dec.decode_symbol(bits_model);
    if (k_ == 0) return static_cast<std::int32_t>(dec.decode_bit(corrector0_)); // 0 or 1
    if (k_ >= 32) return corr_min_;
    std::uint32_t c;
    if (k_ <= bits_high_) {
        c = dec.decode_symbol(corrector(k_));
    } else {
        const std::uint32_t low_bits = k_ - bits_high_;
        c = dec.decode_symbol(corrector(k_));
        c = (c << low_bits) | dec.read_bits(low_bits);
    }
    // Bucket k holds [-(2^k - 1), -2^(k-1)] and [2^(k-1) + 1, 2^k].
    const std::int64_t half = std::int64_t{1} << (k_ - 1);
    std::int64_t v = c;
    v = v >= half ? v + 1 : v - (2 * half - 1);
    return static_cast<std::int32_t>(v);
}

inline std::int32_t IntegerDecoder::decode(ArithmeticDecoder& dec, std::int32_t prediction, std::uint32_t context) {
    const std::int32_t corr = read_corrector(dec, bits_model(context));
    std::int32_t real = static_cast<std::int32_t>(static_cast<std::uint32_t>(prediction) + static_cast<std::uint32_t>(corr));
    if (real < 0) real = static_cast<std::int32_t>(static_cast<std::uint32_t>(real) + corr_range_);
    else if (static_cast<std::uint32_t>(real) >= corr_range_) real = static_cast<std::int32_t>(static_cast<std::uint32_t>(real) - corr_range_);
    return real;
}

} // namespace lasmesh::laz
