// SPDX-License-Identifier: Apache-2.0
// The pointwise items, versions 2 (POINT10, GPSTIME11, RGB12, BYTE) and 1 (WAVEPACKET13), as
// LASzip 2.0 and later write them (Isenburg 2013, section 3.3; LASzip item descriptions).
// Each item keeps the last record it produced and predicts the next one from it.
#pragma once

#include "read/arithmetic_decoder.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace lasmesh::laz {

// X, Y, Z, intensity, return bits, classification, scan angle, user data, point source: 20 bytes.
class Point10Decoder {
  public:
    Point10Decoder(const std::byte* first, ModelStore& store);
    void decode(ArithmeticDecoder& dec, std::byte* out);

  private:
    SymbolModel& lazy(std::array<std::unique_ptr<SymbolModel>, 256>& models, std::uint8_t context, ModelStore& store);

    std::int32_t x_, y_, z_;
    std::uint16_t intensity_;
    std::uint8_t bits_, classification_, scan_angle_, user_data_;
    std::uint16_t point_source_;
    std::array<std::uint16_t, 16> last_intensity_{};
    std::array<Median5, 16> median_x_{}, median_y_{};
    std::array<std::int32_t, 8> last_height_{};
    SymbolModel changed_;
    IntegerDecoder ic_intensity_{16, 4};
    std::array<SymbolModel, 2> scan_angle_models_;
    IntegerDecoder ic_point_source_{16};
    std::array<std::unique_ptr<SymbolModel>, 256> bit_byte_models_, classification_models_, user_data_models_;
    IntegerDecoder ic_dx_{32, 2}, ic_dy_{32, 22}, ic_z_{32, 20};
};

// The GPS time as a double, predicted as a multiple of the last time difference in up to
// four interleaved sequences (Isenburg 2013, section 3.3.2).
class GpsTime11Decoder {
  public:
    GpsTime11Decoder(const std::byte* first, ModelStore& store);
    void decode(ArithmeticDecoder& dec, std::byte* out);

  private:
    std::uint32_t last_ = 0, next_ = 0;
    std::array<std::int64_t, 4> last_time_{}; // the doubles' bit patterns
    std::array<std::int32_t, 4> last_diff_{};
    std::array<std::int32_t, 4> extreme_counter_{};
    LazySymbolModel multi_;
    SymbolModel zero_diff_;
    IntegerDecoder ic_time_{32, 9};
};

// Colour decoding shared by RGB12 v2 and RGB14/RGBNIR14 v3: which bytes changed, then each
// changed byte relative to the last colour and the other channels' change.
struct RgbModels {
    LazySymbolModel used{128};
    std::array<LazySymbolModel, 6> diff{LazySymbolModel(256), LazySymbolModel(256), LazySymbolModel(256),
                                        LazySymbolModel(256), LazySymbolModel(256), LazySymbolModel(256)};
};
void decode_rgb(ArithmeticDecoder& dec, RgbModels& models, std::array<std::uint16_t, 3>& last);

class Rgb12Decoder {
  public:
    explicit Rgb12Decoder(const std::byte* first);
    void decode(ArithmeticDecoder& dec, std::byte* out);

  private:
    std::array<std::uint16_t, 3> last_;
    RgbModels models_;
};

// Extra bytes: each byte relative to its last value, one model per byte.
class ByteDecoder {
  public:
    ByteDecoder(const std::byte* first, std::size_t size);
    void decode(ArithmeticDecoder& dec, std::byte* out);

  private:
    std::vector<std::uint8_t> last_;
    std::vector<LazySymbolModel> models_;
};

// Waveform packet descriptor (29 bytes): index, offset, size, return point, x, y, z.
class WavePacketDecoder {
  public:
    WavePacketDecoder(const std::byte* first, ModelStore& store);
    void decode(ArithmeticDecoder& dec, std::byte* out);

  private:
    std::array<std::byte, 29> last_;
    std::uint32_t last_offset_sym_ = 0;
    std::int32_t last_diff_32_ = 0;
    SymbolModel index_;
    std::array<SymbolModel, 4> offset_sym_;
    IntegerDecoder ic_offset_{32}, ic_size_{32}, ic_return_point_{32}, ic_xyz_{32, 3};
};

} // namespace lasmesh::laz
