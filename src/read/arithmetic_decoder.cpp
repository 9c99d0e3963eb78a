// SPDX-License-Identifier: Apache-2.0
// Range decoder and adaptive models (see the header for the sources).
#include "read/arithmetic_decoder.hpp"

#include <algorithm>
#include <new>

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

SymbolModel::SymbolModel(std::uint32_t n, Fresh) : last_symbol(n - 1), symbols(n), update_cycle(n) {
    // A table of at least as many buckets as symbols, 8 to 256 of them (larger tables made no
    // difference on the corpus and cost small chunks time to build).
    std::uint32_t table_bits = 3;
    while (table_bits < 8 && (1u << table_bits) < n) ++table_bits;
    table_shift = sym_length_shift - table_bits;
    table_last = 1u << table_bits;
    storage_ = std::make_unique_for_overwrite<std::uint16_t[]>(storage_size());
    std::uint16_t* d = storage_.get();
    d[n] = d[n + 1] = 0xFFFF; // no scaled value (cut to 2^15 in decode_symbol) reaches them
    distribution = d;
    table = d + n + 2;
    counts = d + n + 2 + table_last + 2;
    std::fill(counts, counts + n, std::uint16_t{1});
    update();
    update_cycle = symbols_until_update = (n + 6) >> 1;
}

ModelSize& ModelStore::size(std::uint32_t symbols) {
    if (symbols >= by_symbols_.size()) by_symbols_.resize(symbols + 1, nullptr);
    ModelSize*& size = by_symbols_[symbols];
    if (!size) size = &sizes_.emplace_back(ModelSize{SymbolModel(symbols, SymbolModel::Fresh{}), {}});
    return *size;
}

SymbolModel::SymbolModel(std::uint32_t n, ModelStore& store) : home_(&store.size(n)) {
    // Every new model of n symbols starts alike: a copy of the store's fresh one.
    ModelSize& size = *home_;
    const SymbolModel& f = size.fresh;
    distribution = table = counts = nullptr;
    table_shift = f.table_shift, table_last = f.table_last, last_symbol = f.last_symbol, likely = f.likely;
    likely_low = f.likely_low, likely_high = f.likely_high;
    symbols_until_update = f.symbols_until_update, symbols = f.symbols, total_count = f.total_count;
    update_cycle = f.update_cycle;
    if (size.spare.empty()) {
        storage_ = std::make_unique_for_overwrite<std::uint16_t[]>(storage_size());
    } else {
        storage_ = std::move(size.spare.back());
        size.spare.pop_back();
    }
    std::uint16_t* d = storage_.get();
    std::copy(f.storage_.get(), f.storage_.get() + storage_size(), d);
    distribution = d;
    table = d + (f.table - f.distribution);
    counts = d + (f.counts - f.distribution);
}

SymbolModel::~SymbolModel() {
    if (!storage_ || !home_) return;
    try {
        home_->spare.push_back(std::move(storage_));
    } catch (const std::bad_alloc&) {
        // no room to keep it: the memory is freed instead
    }
}

void SymbolModel::update() {
    total_count += update_cycle;
    if (total_count > sym_max_count) {
        total_count = 0;
        for (std::uint32_t k = 0; k < symbols; ++k)
            total_count += (counts[k] = static_cast<std::uint16_t>((counts[k] + 1) >> 1));
    }
    const std::uint32_t scale = 0x80000000u / total_count;
    std::uint16_t* d = storage_.get();
    std::uint16_t* tab = d + symbols + 2;
    // tab[t] = the last symbol whose interval starts before bucket t's start (t << shift) or at
    // it, so d[tab[t]] <= any value in bucket t < d[tab[t + 1] + 1]. That is the number of
    // symbols k >= 1 with d[k] >> shift < t (d increases): each k is stored at its bucket + 1
    // (a later k of the same bucket overwrites an earlier one), then a running maximum fills the
    // buckets between. Without branches: filling bucket by bucket as symbols came mispredicted
    // about 20 times per update.
    std::fill(tab, tab + table_last + 2, std::uint16_t{0});
    std::uint32_t sum = 0, most = 0;
    for (std::uint32_t k = 0; k < symbols; ++k) {
        d[k] = static_cast<std::uint16_t>((scale * sum) >> (31 - sym_length_shift)); // below 2^15
        if (counts[k] > most) most = counts[k], likely = k;
        sum += counts[k];
        // d[k] < 2^15, so the index is at most table_last; k = 0 goes to 1, harmlessly.
        tab[(d[k] >> table_shift) + 1] = static_cast<std::uint16_t>(k);
    }
    for (std::uint32_t t = 1, run = 0; t <= table_last + 1; ++t)
        tab[t] = static_cast<std::uint16_t>(run = std::max<std::uint32_t>(run, tab[t]));
    likely_low = d[likely];
    likely_high = d[likely + 1]; // the sentinel for the last symbol (unused: its interval ends at the length)
    // A first guess right less than 40% of the time costs more in mispredicted branches than it
    // saves in divisions (measured: format 3 +3-4% with this cut against none; 50% and 25% did
    // less well, 30% about the same): such a model gets the empty interval [0, 0) as its guess,
    // which never holds the value, so decode_symbol always takes the division and its branch
    // stays predictable. likely = 0 is not the last symbol (there are at least two).
    if (5 * std::uint64_t{most} < 2 * std::uint64_t{sum}) {
        likely = 0;
        likely_low = likely_high = 0;
    }
    update_cycle = (5 * update_cycle) >> 2;
    const std::uint32_t max_cycle = (symbols + 6) << 3;
    if (update_cycle > max_cycle) update_cycle = max_cycle;
    symbols_until_update = update_cycle;
}

ArithmeticDecoder::ArithmeticDecoder(std::span<const std::byte> bytes, ModelStore& store)
    : data_(bytes.data()), store_(&store), size_(bytes.size()) {
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

} // namespace lasmesh::laz
