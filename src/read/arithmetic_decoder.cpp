// Range decoder and adaptive models (see the header for the sources).
#include "read/arithmetic_decoder.hpp"

namespace lasmesh::laz {


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
