// Range decoder and adaptive models (see the header for the sources).
#include "read/arithmetic_decoder.hpp"

namespace lasmesh::laz {

namespace {
constexpr std::uint32_t bit_length_shift = 13;    // bit model probabilities are 13-bit
constexpr std::uint32_t bit_max_count = 1u << 13; // halve the counts beyond this
constexpr std::uint32_t sym_length_shift = 15;    // symbol distributions are 15-bit
constexpr std::uint32_t sym_max_count = 1u << 15;
constexpr std::uint32_t min_length = 1u << 24; // renormalize below this interval length
} // namespace

void BitModel::update() {
    bit_count += update_cycle;
    if (bit_count > bit_max_count) {
        bit_count = (bit_count + 1) >> 1;
        bit_0_count = (bit_0_count + 1) >> 1;
        if (bit_0_count == bit_count) ++bit_count;
    }
    const std::uint32_t scale = 0x80000000u / bit_count;
    bit_0_prob = (bit_0_count * scale) >> (31 - bit_length_shift);
    update_cycle = (5 * update_cycle) >> 2;
    if (update_cycle > 64) update_cycle = 64;
    bits_until_update = update_cycle;
}

SymbolModel::SymbolModel(std::uint32_t n)
    : symbols(n), last_symbol(n - 1), update_cycle(n), distribution(n), counts(n, 1) {
    if (n > 16) {
        std::uint32_t table_bits = 3;
        while (n > (1u << (table_bits + 2))) ++table_bits;
        table.resize((1u << table_bits) + 2);
        table_shift = sym_length_shift - table_bits;
    }
    update();
    update_cycle = symbols_until_update = (n + 6) >> 1;
}

void SymbolModel::update() {
    total_count += update_cycle;
    if (total_count > sym_max_count) {
        total_count = 0;
        for (auto& c : counts) total_count += (c = (c + 1) >> 1);
    }
    const std::uint32_t scale = 0x80000000u / total_count;
    std::uint32_t sum = 0;
    if (table.empty()) {
        for (std::uint32_t k = 0; k < symbols; ++k) {
            distribution[k] = (scale * sum) >> (31 - sym_length_shift);
            sum += counts[k];
        }
    } else {
        // table[t] = first symbol whose interval can contain a value with top bits t.
        const std::uint32_t table_size = static_cast<std::uint32_t>(table.size()) - 2;
        std::uint32_t s = 0;
        for (std::uint32_t k = 0; k < symbols; ++k) {
            distribution[k] = (scale * sum) >> (31 - sym_length_shift);
            sum += counts[k];
            const std::uint32_t w = distribution[k] >> table_shift;
            while (s < w) table[++s] = k - 1;
        }
        table[0] = 0;
        while (s <= table_size) table[++s] = symbols - 1;
    }
    update_cycle = (5 * update_cycle) >> 2;
    const std::uint32_t max_cycle = (symbols + 6) << 3;
    if (update_cycle > max_cycle) update_cycle = max_cycle;
    symbols_until_update = update_cycle;
}

ArithmeticDecoder::ArithmeticDecoder(std::span<const std::byte> bytes) : data_(bytes.data()), size_(bytes.size()) {
    for (int i = 0; i < 4; ++i) value_ = (value_ << 8) | next_byte();
}

std::uint32_t ArithmeticDecoder::decode_bit(BitModel& m) {
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

std::uint32_t ArithmeticDecoder::decode_symbol(SymbolModel& m) {
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

std::uint32_t ArithmeticDecoder::read_short_bits(std::uint32_t bits) {
    length_ >>= bits;
    std::uint32_t sym = value_ / length_;
    value_ -= length_ * sym;
    if (length_ < min_length) renormalize();
    return sym;
}

std::uint32_t ArithmeticDecoder::read_bits(std::uint32_t bits) {
    // More than 19 bits are sent as a low 16-bit part, then the rest.
    if (bits > 19) {
        const std::uint32_t low = read_short_bits(16);
        return (read_bits(bits - 16) << 16) | low;
    }
    return read_short_bits(bits);
}

IntegerDecoder::IntegerDecoder(std::uint32_t bits, std::uint32_t contexts, std::uint32_t bits_high)
    : bits_high_(bits_high) {
    if (bits && bits < 32) {
        corr_bits_ = bits;
        corr_range_ = 1u << bits;
        corr_min_ = -static_cast<std::int32_t>(corr_range_ / 2);
    } else {
        corr_bits_ = 32;
        corr_range_ = 0; // values wrap around 2^32 by themselves
        corr_min_ = INT32_MIN;
    }
    bits_models_.resize(contexts);
    correctors_.resize(corr_bits_);
}

SymbolModel& IntegerDecoder::bits_model(std::uint32_t context) {
    auto& m = bits_models_[context];
    if (!m) m = std::make_unique<SymbolModel>(corr_bits_ + 1);
    return *m;
}

SymbolModel& IntegerDecoder::corrector(std::uint32_t k) {
    auto& m = correctors_[k - 1];
    if (!m) m = std::make_unique<SymbolModel>(k <= bits_high_ ? 1u << k : 1u << bits_high_);
    return *m;
}

std::int32_t IntegerDecoder::read_corrector(ArithmeticDecoder& dec, SymbolModel& bits_model) {
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

std::int32_t IntegerDecoder::decode(ArithmeticDecoder& dec, std::int32_t prediction, std::uint32_t context) {
    const std::int32_t corr = read_corrector(dec, bits_model(context));
    std::int32_t real = static_cast<std::int32_t>(static_cast<std::uint32_t>(prediction) + static_cast<std::uint32_t>(corr));
    if (real < 0) real = static_cast<std::int32_t>(static_cast<std::uint32_t>(real) + corr_range_);
    else if (static_cast<std::uint32_t>(real) >= corr_range_) real = static_cast<std::int32_t>(static_cast<std::uint32_t>(real) - corr_range_);
    return real;
}

void Median5::add(std::int32_t x) {
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

} // namespace lasmesh::laz
