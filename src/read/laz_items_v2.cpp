// SPDX-License-Identifier: Apache-2.0
// Pointwise items v2 (and WAVEPACKET13 v1): see the header.
#include "read/laz_items_v2.hpp"

#include "byte_order.hpp"
#include "read/laz_gps_time.hpp"
#include "read/laz_vlr.hpp"

#include <cstring>

namespace lasmesh::laz {

namespace {

// Contexts from (number of returns n, return number r): which of 16 return "shapes" a point
// has (first of many, last, single, ...), for the X/Y predictors; the level |n - r| for Z.
constexpr std::uint8_t return_map[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8},  {14, 0, 1, 3, 6, 10, 10, 9},    {13, 1, 2, 4, 7, 11, 11, 10},
    {12, 3, 4, 5, 8, 12, 12, 11},    {11, 6, 7, 8, 9, 13, 13, 12},   {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15},
};
constexpr std::uint8_t return_level(unsigned n, unsigned r) {
    return static_cast<std::uint8_t>(n > r ? n - r : r - n);
}

inline std::uint8_t clamp_u8(std::int32_t v) {
    return static_cast<std::uint8_t>(v < 0 ? 0 : v > 255 ? 255 : v);
}

// GPS time multipliers (Isenburg 2013, 3.3.2): codes 1..499 multiply the last difference,
// 500 is the largest, 501..510 are -1..-10, 511 unchanged, 512 a full new time, 513..515
// switch to another of the four sequences.
constexpr std::int32_t gps_pointwise_unchanged = gps_multi - gps_multi_minus + 1; // 511
constexpr std::int32_t gps_pointwise_code_full = gps_multi - gps_multi_minus + 2; // 512
constexpr std::int32_t gps_pointwise_total = gps_multi - gps_multi_minus + 6;     // 516

} // namespace

Point10Decoder::Point10Decoder(const std::byte* p, ModelStore& store)
    : x_(load_le<std::int32_t>(p)), y_(load_le<std::int32_t>(p + 4)), z_(load_le<std::int32_t>(p + 8)),
      intensity_(0), // v2 predicts intensity from last_intensity_, which starts at 0
      bits_(std::to_integer<std::uint8_t>(p[14])), classification_(std::to_integer<std::uint8_t>(p[15])),
      scan_angle_(std::to_integer<std::uint8_t>(p[16])), user_data_(std::to_integer<std::uint8_t>(p[17])),
      point_source_(load_le<std::uint16_t>(p + 18)),
      changed_(64, store), scan_angle_models_{SymbolModel(256, store), SymbolModel(256, store)} {}

SymbolModel& Point10Decoder::lazy(std::array<std::unique_ptr<SymbolModel>, 256>& models, std::uint8_t context,
                                  ModelStore& store) {
    if (!models[context]) models[context] = std::make_unique<SymbolModel>(256, store);
    return *models[context];
}

void Point10Decoder::decode(ArithmeticDecoder& decoder, std::byte* out) {
    ArithmeticDecoder dec = decoder; // a local the compiler keeps in registers
    const std::uint32_t changed = dec.decode_symbol(changed_);
    unsigned r, n, m, l;
    if (changed) {
        if (changed & 32)
            bits_ = static_cast<std::uint8_t>(dec.decode_symbol(lazy(bit_byte_models_, bits_, dec.store())));
        r = bits_ & 7;
        n = (bits_ >> 3) & 7;
        m = return_map[n][r];
        l = return_level(n, r);
        if (changed & 16) {
            intensity_ = static_cast<std::uint16_t>(ic_intensity_.decode(dec, last_intensity_[m], m < 3 ? m : 3));
            last_intensity_[m] = intensity_;
        } else {
            intensity_ = last_intensity_[m];
        }
        if (changed & 8)
            classification_ = static_cast<std::uint8_t>(
                dec.decode_symbol(lazy(classification_models_, classification_, dec.store())));
        if (changed & 4) {
            const std::uint32_t v = dec.decode_symbol(scan_angle_models_[(bits_ >> 6) & 1]);
            scan_angle_ = static_cast<std::uint8_t>(v + scan_angle_);
        }
        if (changed & 2)
            user_data_ = static_cast<std::uint8_t>(dec.decode_symbol(lazy(user_data_models_, user_data_, dec.store())));
        if (changed & 1) point_source_ = static_cast<std::uint16_t>(ic_point_source_.decode(dec, point_source_));
    } else {
        r = bits_ & 7;
        n = (bits_ >> 3) & 7;
        m = return_map[n][r];
        l = return_level(n, r);
    }
    // X, Y: difference to the last point predicted by the median of the last five differences
    // in the same return context; the bit length of X's correction is context for Y, both for Z.
    std::int32_t diff = ic_dx_.decode(dec, median_x_[m].get(), n == 1);
    x_ = static_cast<std::int32_t>(static_cast<std::uint32_t>(x_) + static_cast<std::uint32_t>(diff));
    median_x_[m].add(diff);
    std::uint32_t k = ic_dx_.k();
    diff = ic_dy_.decode(dec, median_y_[m].get(), (n == 1) + (k < 20 ? k & ~1u : 20));
    y_ = static_cast<std::int32_t>(static_cast<std::uint32_t>(y_) + static_cast<std::uint32_t>(diff));
    median_y_[m].add(diff);
    k = (ic_dx_.k() + ic_dy_.k()) / 2;
    z_ = ic_z_.decode(dec, last_height_[l], (n == 1) + (k < 18 ? k & ~1u : 18));
    last_height_[l] = z_;

    store_le(out, x_);
    store_le(out + 4, y_);
    store_le(out + 8, z_);
    store_le(out + 12, intensity_);
    out[14] = std::byte{bits_};
    out[15] = std::byte{classification_};
    out[16] = std::byte{scan_angle_};
    out[17] = std::byte{user_data_};
    store_le(out + 18, point_source_);
    decoder = dec;
}

GpsTime11Decoder::GpsTime11Decoder(const std::byte* first, ModelStore& store)
    : multi_(gps_pointwise_total), zero_diff_(6, store) {
    last_time_[0] = load_le<std::int64_t>(first);
}

void GpsTime11Decoder::decode(ArithmeticDecoder& decoder, std::byte* out) {
    ArithmeticDecoder dec = decoder; // a local the compiler keeps in registers
    auto full_time = [&] {
        next_ = (next_ + 1) & 3;
        const std::uint32_t high = static_cast<std::uint32_t>(
            ic_time_.decode(dec, static_cast<std::int32_t>(static_cast<std::uint64_t>(last_time_[last_]) >> 32), 8));
        const std::uint32_t low = dec.read_int();
        last_time_[next_] = static_cast<std::int64_t>((std::uint64_t{high} << 32) | low);
        last_ = next_;
        last_diff_[last_] = 0;
        extreme_counter_[last_] = 0;
    };
    // A switch to another sequence decodes that sequence's time; a valid stream switches at most
    // once per point, so more switches mean corrupt data.
    for (int switches = 0;; ++switches) {
        if (switches > 4) throw ChunkError(dec.position(), "GPS time switches sequence endlessly (corrupt data)");
        if (last_diff_[last_] == 0) {
            const std::uint32_t multi = dec.decode_symbol(zero_diff_);
            if (multi == 1) {
                last_diff_[last_] = ic_time_.decode(dec, 0, 0);
                last_time_[last_] = add64(last_time_[last_], last_diff_[last_]);
                extreme_counter_[last_] = 0;
            } else if (multi == 2) {
                full_time();
            } else if (multi > 2) {
                last_ = (last_ + multi - 2) & 3;
                continue;
            }
            break;
        }
        const std::int32_t multi = static_cast<std::int32_t>(dec.decode_symbol(multi_));
        if (multi < gps_pointwise_unchanged) {
            // Extreme multipliers count towards replacing the reference difference.
            const auto [prediction, context, extreme] = predict_gps_difference(multi, last_diff_[last_]);
            const std::int32_t diff = ic_time_.decode(dec, prediction, context);
            last_time_[last_] = add64(last_time_[last_], diff);
            if (multi == 1) {
                extreme_counter_[last_] = 0;
            } else if (extreme && ++extreme_counter_[last_] > 3) {
                // A run of extreme multipliers makes the new difference the reference.
                last_diff_[last_] = diff;
                extreme_counter_[last_] = 0;
            }
        } else if (multi == gps_pointwise_code_full) {
            full_time();
        } else if (multi > gps_pointwise_code_full) {
            last_ = (last_ + static_cast<std::uint32_t>(multi - gps_pointwise_code_full)) & 3;
            continue;
        }
        break;
    }
    decoder = dec;
    store_le(out, last_time_[last_]);
}

void decode_rgb(ArithmeticDecoder& decoder, RgbModels& models, std::array<std::uint16_t, 3>& last) {
    ArithmeticDecoder dec = decoder; // a local the compiler keeps in registers
    // Bits 0-5 of `used`: low/high byte of R, G, B changed (order R lo, R hi, G lo, G hi, B lo,
    // B hi); bit 6: the colour is not grey, so G and B are coded too, predicted from R's change.
    const std::uint32_t used = dec.decode_symbol(models.used);
    std::array<std::uint16_t, 3> c;
    auto byte_of = [](std::uint16_t v, int high) { return static_cast<std::int32_t>(high ? v >> 8 : v & 0xFF); };
    auto sym = [&](int i) { return static_cast<std::int32_t>(dec.decode_symbol(models.diff[i])); };
    std::int32_t lo = used & 1 ? static_cast<std::uint8_t>(sym(0) + byte_of(last[0], 0)) : byte_of(last[0], 0);
    std::int32_t hi = used & 2 ? static_cast<std::uint8_t>(sym(1) + byte_of(last[0], 1)) : byte_of(last[0], 1);
    c[0] = static_cast<std::uint16_t>(lo | hi << 8);
    if (used & 64) {
        std::int32_t diff = byte_of(c[0], 0) - byte_of(last[0], 0);
        std::int32_t g_lo =
            used & 4 ? static_cast<std::uint8_t>(sym(2) + clamp_u8(diff + byte_of(last[1], 0))) : byte_of(last[1], 0);
        std::int32_t b_lo = byte_of(last[2], 0);
        if (used & 16) {
            const std::int32_t d = (diff + (g_lo - byte_of(last[1], 0))) / 2;
            b_lo = static_cast<std::uint8_t>(sym(4) + clamp_u8(d + byte_of(last[2], 0)));
        }
        diff = byte_of(c[0], 1) - byte_of(last[0], 1);
        std::int32_t g_hi =
            used & 8 ? static_cast<std::uint8_t>(sym(3) + clamp_u8(diff + byte_of(last[1], 1))) : byte_of(last[1], 1);
        std::int32_t b_hi = byte_of(last[2], 1);
        if (used & 32) {
            const std::int32_t d = (diff + (g_hi - byte_of(last[1], 1))) / 2;
            b_hi = static_cast<std::uint8_t>(sym(5) + clamp_u8(d + byte_of(last[2], 1)));
        }
        c[1] = static_cast<std::uint16_t>(g_lo | g_hi << 8);
        c[2] = static_cast<std::uint16_t>(b_lo | b_hi << 8);
    } else {
        c[1] = c[2] = c[0];
    }
    last = c;
    decoder = dec;
}

Rgb12Decoder::Rgb12Decoder(const std::byte* p)
    : last_{load_le<std::uint16_t>(p), load_le<std::uint16_t>(p + 2), load_le<std::uint16_t>(p + 4)} {}

void Rgb12Decoder::decode(ArithmeticDecoder& dec, std::byte* out) {
    decode_rgb(dec, models_, last_);
    for (int i = 0; i < 3; ++i) store_le(out + 2 * i, last_[i]);
}

ByteDecoder::ByteDecoder(const std::byte* first, std::size_t size) : last_(size) {
    std::memcpy(last_.data(), first, size);
    for (std::size_t i = 0; i < size; ++i) models_.emplace_back(256);
}

void ByteDecoder::decode(ArithmeticDecoder& decoder, std::byte* out) {
    ArithmeticDecoder dec = decoder;
    for (std::size_t i = 0; i < last_.size(); ++i) {
        last_[i] = static_cast<std::uint8_t>(last_[i] + dec.decode_symbol(models_[i]));
        out[i] = std::byte{last_[i]};
    }
    decoder = dec;
}

WavePacketDecoder::WavePacketDecoder(const std::byte* first, ModelStore& store)
    : index_(256, store), offset_sym_{SymbolModel(4, store), SymbolModel(4, store), SymbolModel(4, store),
                                      SymbolModel(4, store)} {
    std::memcpy(last_.data(), first, last_.size());
}

void WavePacketDecoder::decode(ArithmeticDecoder& dec, std::byte* out) {
    out[0] = std::byte{static_cast<std::uint8_t>(dec.decode_symbol(index_))};
    const std::byte* l = last_.data() + 1;
    const std::uint64_t last_offset = load_le<std::uint64_t>(l);
    const std::uint32_t last_size = load_le<std::uint32_t>(l + 8);
    // Offset: same as last, right after the last packet, last plus a 32-bit difference, or raw.
    last_offset_sym_ = dec.decode_symbol(offset_sym_[last_offset_sym_]);
    std::uint64_t offset;
    if (last_offset_sym_ == 0)
        offset = last_offset;
    else if (last_offset_sym_ == 1)
        offset = last_offset + last_size;
    else if (last_offset_sym_ == 2) {
        last_diff_32_ = ic_offset_.decode(dec, last_diff_32_);
        offset = last_offset + static_cast<std::uint64_t>(static_cast<std::int64_t>(last_diff_32_));
    } else {
        const std::uint64_t low = dec.read_int();
        offset = (std::uint64_t{dec.read_int()} << 32) | low;
    }
    std::byte* o = out + 1;
    store_le(o, offset);
    store_le(o + 8, static_cast<std::uint32_t>(ic_size_.decode(dec, static_cast<std::int32_t>(last_size))));
    store_le(o + 12, ic_return_point_.decode(dec, load_le<std::int32_t>(l + 12)));
    for (int i = 0; i < 3; ++i) store_le(o + 16 + 4 * i, ic_xyz_.decode(dec, load_le<std::int32_t>(l + 16 + 4 * i), i));
    std::memcpy(last_.data(), out, last_.size());
}

} // namespace lasmesh::laz
