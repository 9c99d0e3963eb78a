// SPDX-License-Identifier: Apache-2.0
// Layered chunks (compressor 3): POINT14, RGB14, RGBNIR14, BYTE14 and WAVEPACKET14, versions
// 3 and 4 (LASzip 3.x; the LAS 1.4 R15 point formats 6-10). Each item keeps up to four
// contexts, one per scanner channel, and switches with the point's channel.
#include "read/laz_layered.hpp"

#include "byte_order.hpp"
#include "read/arithmetic_decoder.hpp"
#include "read/laz_chunks.hpp"
#include "read/laz_gps_time.hpp"
#include "read/laz_items_v2.hpp"

#include <array>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

namespace lasmesh::laz {

namespace {

// Return contexts for up to 15 returns: X/Y predictors by return "shape" (6 contexts), Z by
// the distance |n - r| capped at 7 (8 contexts). The table is part of the format.
constexpr std::uint8_t return_map_6ctx[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5}, {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3}, {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5},
};
inline std::uint32_t return_level_8ctx(std::uint32_t n, std::uint32_t r) {
    const std::uint32_t d = n > r ? n - r : r - n;
    return d > 7 ? 7 : d;
}

// GPS time codes in v3: as in GPSTIME11 v2 but without an "unchanged" code (the changed-values
// symbol says whether the time changed): 511 = full time, 512..514 = switch sequence.
constexpr std::int32_t gps_layered_code_full = gps_multi - gps_multi_minus + 1; // 511
constexpr std::int32_t gps_layered_total = gps_multi - gps_multi_minus + 5;     // 515

struct Layer {
    std::span<const std::byte> bytes;
    ArithmeticDecoder dec;
    bool present = false; // a 0-byte layer: the field keeps its first-record value
    const char* name = "";
};

template <std::size_t N>
SymbolModel& lazy(std::array<std::unique_ptr<SymbolModel>, N>& models, std::size_t i, std::uint32_t symbols,
                  ModelStore& store) {
    if (!models[i]) models[i] = std::make_unique<SymbolModel>(symbols, store);
    return *models[i];
}

// The last point of one scanner channel, and the models that predict its successor.
struct Point14Context {
    // fields of the last point
    std::int32_t x = 0, y = 0, z = 0;
    std::uint16_t intensity = 0;
    std::uint32_t r = 0, n = 0;
    std::uint8_t class_flags = 0, channel = 0, scan_dir = 0, edge = 0, classification = 0, user_data = 0;
    std::int16_t scan_angle = 0;
    std::uint16_t point_source = 0;
    std::int64_t gps = 0; // the double's bits
    bool gps_changed = false;

    std::array<LazySymbolModel, 8> changed{LazySymbolModel(128), LazySymbolModel(128), LazySymbolModel(128),
                                           LazySymbolModel(128), LazySymbolModel(128), LazySymbolModel(128),
                                           LazySymbolModel(128), LazySymbolModel(128)};
    LazySymbolModel scanner_channel{3};
    std::array<std::unique_ptr<SymbolModel>, 16> number_of_returns, return_number;
    LazySymbolModel return_number_gps_same{13};
    IntegerDecoder ic_dx{32, 2}, ic_dy{32, 22}, ic_z{32, 20};
    std::array<std::unique_ptr<SymbolModel>, 64> classification_models, flags_models, user_data_models;
    IntegerDecoder ic_intensity{16, 4}, ic_scan_angle{16, 2}, ic_point_source{16};
    LazySymbolModel gps_multi_model{gps_layered_total}, gps_zero_diff{5};
    IntegerDecoder ic_gps{32, 9};
    std::uint32_t gps_last = 0, gps_next = 0;
    std::array<std::int64_t, 4> gps_times{};
    std::array<std::int32_t, 4> gps_diffs{}, gps_extreme{};
    std::array<std::uint16_t, 8> last_intensity{};
    std::array<Median5, 12> median_x{}, median_y{};
    std::array<std::int32_t, 8> last_z{};

    // A context starts from the last point seen (the chunk's first, or another channel's).
    void start_from(const Point14Context& p) {
        x = p.x, y = p.y, z = p.z, intensity = p.intensity, r = p.r, n = p.n;
        class_flags = p.class_flags, channel = p.channel, scan_dir = p.scan_dir, edge = p.edge;
        classification = p.classification, user_data = p.user_data, scan_angle = p.scan_angle;
        point_source = p.point_source, gps = p.gps, gps_changed = false;
        last_z.fill(z);
        last_intensity.fill(intensity);
        gps_times = {gps, 0, 0, 0};
    }
};

class Point14Decoder {
  public:
    Point14Decoder(const std::byte* raw, Layer* layers, std::uint16_t version) : layers_(layers), version_(version) {
        Point14Context first;
        first.x = load_le<std::int32_t>(raw);
        first.y = load_le<std::int32_t>(raw + 4);
        first.z = load_le<std::int32_t>(raw + 8);
        first.intensity = load_le<std::uint16_t>(raw + 12);
        const auto returns = std::to_integer<std::uint32_t>(raw[14]);
        first.r = returns & 15;
        first.n = returns >> 4;
        const auto flags = std::to_integer<std::uint8_t>(raw[15]);
        first.class_flags = flags & 15;
        first.channel = (flags >> 4) & 3;
        first.scan_dir = (flags >> 6) & 1;
        first.edge = flags >> 7;
        first.classification = std::to_integer<std::uint8_t>(raw[16]);
        first.user_data = std::to_integer<std::uint8_t>(raw[17]);
        first.scan_angle = load_le<std::int16_t>(raw + 18);
        first.point_source = load_le<std::uint16_t>(raw + 20);
        first.gps = load_le<std::int64_t>(raw + 22);
        current_ = published_ = first.channel;
        contexts_[current_] = std::make_unique<Point14Context>();
        contexts_[current_]->start_from(first);
    }
    // The channel the other items follow. Version 3 publishes it only on the point where the
    // channel changes and 0 on all others (LASzip issue #74, kept by every v3 writer and
    // reader); version 4 publishes the current channel on every point.
    std::uint32_t context() const { return published_; }
    void decode(std::byte* out);

  private:
    void decode_gps(Point14Context& c);

    Layer* layers_; // 9: XY+returns, Z, class, flags, intensity, angle, user data, source, time
    std::uint16_t version_;
    std::array<std::unique_ptr<Point14Context>, 4> contexts_;
    std::uint32_t current_ = 0;
    std::uint32_t published_ = 0;
};

void Point14Decoder::decode_gps(Point14Context& c) {
    ArithmeticDecoder dec = layers_[8].dec; // a local the compiler keeps in registers
    auto full_time = [&] {
        c.gps_next = (c.gps_next + 1) & 3;
        const std::uint32_t high = static_cast<std::uint32_t>(c.ic_gps.decode(
            dec, static_cast<std::int32_t>(static_cast<std::uint64_t>(c.gps_times[c.gps_last]) >> 32), 8));
        const std::uint32_t low = dec.read_int();
        c.gps_times[c.gps_next] = static_cast<std::int64_t>((std::uint64_t{high} << 32) | low);
        c.gps_last = c.gps_next;
        c.gps_diffs[c.gps_last] = 0;
        c.gps_extreme[c.gps_last] = 0;
    };
    // A switch to another sequence decodes that sequence's time; a valid stream switches at most
    // once per point, so more switches mean corrupt data.
    for (int switches = 0;; ++switches) {
        if (switches > 4) throw ChunkError(0, "GPS time switches sequence endlessly (corrupt data)");
        const std::uint32_t l = c.gps_last;
        if (c.gps_diffs[l] == 0) {
            const std::uint32_t multi = dec.decode_symbol(c.gps_zero_diff);
            if (multi == 0) {
                c.gps_diffs[l] = c.ic_gps.decode(dec, 0, 0);
                c.gps_times[l] = add64(c.gps_times[l], c.gps_diffs[l]);
                c.gps_extreme[l] = 0;
            } else if (multi == 1) {
                full_time();
            } else {
                c.gps_last = (l + multi - 1) & 3;
                continue;
            }
            break;
        }
        const std::int32_t multi = static_cast<std::int32_t>(dec.decode_symbol(c.gps_multi_model));
        if (multi < gps_layered_code_full) {
            // Extreme multipliers count towards replacing the reference difference.
            const auto [prediction, context, extreme] = predict_gps_difference(multi, c.gps_diffs[l]);
            const std::int32_t diff = c.ic_gps.decode(dec, prediction, context);
            c.gps_times[l] = add64(c.gps_times[l], diff);
            if (multi == 1) {
                c.gps_extreme[l] = 0;
            } else if (extreme && ++c.gps_extreme[l] > 3) {
                c.gps_diffs[l] = diff;
                c.gps_extreme[l] = 0;
            }
        } else if (multi == gps_layered_code_full) {
            full_time();
        } else {
            c.gps_last = (l + static_cast<std::uint32_t>(multi - gps_layered_code_full)) & 3;
            continue;
        }
        break;
    }
    layers_[8].dec = dec;
}

void Point14Decoder::decode(std::byte* out) {
    ArithmeticDecoder xy = layers_[0].dec; // a local the compiler keeps in registers
    Point14Context* c = contexts_[current_].get();
    // Context of the changed-values symbol: was the last point a first return, a last return,
    // and did its GPS time change.
    const std::uint32_t lpr = (c->r == 1 ? 1u : 0u) + (c->r >= c->n ? 2u : 0u) + (c->gps_changed ? 4u : 0u);
    const std::uint32_t changed = xy.decode_symbol(c->changed[lpr]);
    if (changed & (1u << 6)) {
        // The scanner channel changed: continue in that channel's context, starting a new one
        // from this channel's last point.
        const std::uint32_t diff = xy.decode_symbol(c->scanner_channel);
        const std::uint32_t channel = (current_ + diff + 1) % 4;
        if (!contexts_[channel]) {
            contexts_[channel] = std::make_unique<Point14Context>();
            contexts_[channel]->start_from(*c);
        }
        current_ = channel;
        c = contexts_[current_].get();
        c->channel = static_cast<std::uint8_t>(channel);
        published_ = channel;
    } else {
        published_ = version_ >= 4 ? current_ : 0;
    }
    const bool point_source_change = changed & (1u << 5);
    const bool gps_change = changed & (1u << 4);
    const bool scan_angle_change = changed & (1u << 3);

    const std::uint32_t last_n = c->n, last_r = c->r;
    std::uint32_t n = last_n, r = last_r;
    if (changed & (1u << 2)) n = c->n = xy.decode_symbol(lazy(c->number_of_returns, last_n, 16, xy.store()));
    switch (changed & 3) {
    case 0: break;
    case 1: r = (last_r + 1) % 16; break;
    case 2: r = (last_r + 15) % 16; break;
    default:
        if (gps_change)
            r = xy.decode_symbol(lazy(c->return_number, last_r, 16, xy.store()));
        else
            r = (last_r + xy.decode_symbol(c->return_number_gps_same) + 2) % 16;
        break;
    }
    c->r = r;
    const std::uint32_t m = return_map_6ctx[n][r];
    const std::uint32_t l = return_level_8ctx(n, r);
    // single (3), first (2), last (1) or intermediate (0) return
    const std::uint32_t cpr = (r == 1 ? 2u : 0u) + (r >= n ? 1u : 0u);
    const std::uint32_t median_index = (m << 1) | (gps_change ? 1u : 0u);

    std::int32_t diff = c->ic_dx.decode(xy, c->median_x[median_index].get(), n == 1);
    c->x = add32(c->x, diff);
    c->median_x[median_index].add(diff);
    std::uint32_t k = c->ic_dx.k();
    diff = c->ic_dy.decode(xy, c->median_y[median_index].get(), (n == 1) + (k < 20 ? k & ~1u : 20));
    c->y = add32(c->y, diff);
    c->median_y[median_index].add(diff);
    layers_[0].dec = xy;
    if (layers_[1].present) {
        k = (c->ic_dx.k() + c->ic_dy.k()) / 2;
        c->z = c->ic_z.decode(layers_[1].dec, c->last_z[l], (n == 1) + (k < 18 ? k & ~1u : 18));
        c->last_z[l] = c->z;
    }
    if (layers_[2].present) {
        const std::uint32_t ccc = ((c->classification & 0x1Fu) << 1) + (cpr == 3 ? 1u : 0u);
        c->classification = static_cast<std::uint8_t>(
            layers_[2].dec.decode_symbol(lazy(c->classification_models, ccc, 256, layers_[2].dec.store())));
    }
    if (layers_[3].present) {
        const std::uint32_t last_flags = (c->edge << 5) | (c->scan_dir << 4) | c->class_flags;
        const std::uint32_t flags =
            layers_[3].dec.decode_symbol(lazy(c->flags_models, last_flags, 64, layers_[3].dec.store()));
        c->edge = (flags >> 5) & 1;
        c->scan_dir = (flags >> 4) & 1;
        c->class_flags = flags & 15;
    }
    if (layers_[4].present) {
        const std::uint32_t i = (cpr << 1) | (gps_change ? 1u : 0u);
        c->intensity = static_cast<std::uint16_t>(c->ic_intensity.decode(layers_[4].dec, c->last_intensity[i], cpr));
        c->last_intensity[i] = c->intensity;
    }
    if (layers_[5].present && scan_angle_change)
        c->scan_angle = static_cast<std::int16_t>(c->ic_scan_angle.decode(layers_[5].dec, c->scan_angle, gps_change));
    if (layers_[6].present)
        c->user_data = static_cast<std::uint8_t>(
            layers_[6].dec.decode_symbol(lazy(c->user_data_models, c->user_data / 4u, 256, layers_[6].dec.store())));
    if (layers_[7].present && point_source_change)
        c->point_source = static_cast<std::uint16_t>(c->ic_point_source.decode(layers_[7].dec, c->point_source));
    if (layers_[8].present && gps_change) {
        decode_gps(*c);
        c->gps = c->gps_times[c->gps_last];
    }
    c->gps_changed = gps_change;

    store_le(out, c->x);
    store_le(out + 4, c->y);
    store_le(out + 8, c->z);
    store_le(out + 12, c->intensity);
    out[14] = std::byte(static_cast<std::uint8_t>((c->r & 15) | (c->n << 4)));
    out[15] =
        std::byte(static_cast<std::uint8_t>(c->class_flags | (c->channel << 4) | (c->scan_dir << 6) | (c->edge << 7)));
    out[16] = std::byte{c->classification};
    out[17] = std::byte{c->user_data};
    store_le(out + 18, c->scan_angle);
    store_le(out + 20, c->point_source);
    store_le(out + 22, c->gps);
}

// Per-channel state of the items after POINT14. On a switch to a channel seen the first time,
// its state starts from the current channel's last value. On a switch to a channel already
// used, version 3 predicts (and stores) that one point from the previous channel's last value,
// as LASzip 3.x does; version 4 uses the channel's own.
template <typename State>
class Channels {
  public:
    Channels(std::uint32_t channel, State first, std::uint16_t version)
        : version_(version), current_(channel), last_(channel) {
        states_[channel].emplace(std::move(first));
    }
    template <typename Fresh>
    void follow(std::uint32_t channel, Fresh fresh) {
        last_ = current_;
        if (channel == current_) return;
        current_ = channel;
        if (!states_[channel]) {
            states_[channel].emplace(fresh(*states_[last_]));
            last_ = channel;
        } else if (version_ >= 4) {
            last_ = channel;
        }
    }
    State& models() { return *states_[current_]; }
    State& last() { return *states_[last_]; }

  private:
    std::uint16_t version_;
    std::uint32_t current_, last_;
    std::array<std::optional<State>, 4> states_;
};

struct RgbState {
    std::array<std::uint16_t, 3> last;
    std::uint16_t nir = 0;
    std::unique_ptr<RgbModels> rgb = std::make_unique<RgbModels>();
    std::unique_ptr<LazySymbolModel> nir_used = std::make_unique<LazySymbolModel>(4);
    std::unique_ptr<std::array<LazySymbolModel, 2>> nir_diff = std::make_unique<std::array<LazySymbolModel, 2>>(
        std::array<LazySymbolModel, 2>{LazySymbolModel(256), LazySymbolModel(256)});
};

struct ByteState {
    std::vector<std::uint8_t> last;
    std::vector<LazySymbolModel> models;
    static ByteState from(std::vector<std::uint8_t> last) {
        ByteState s{std::move(last), {}};
        for (std::size_t i = 0; i < s.last.size(); ++i) s.models.emplace_back(256);
        return s;
    }
};

struct WaveState {
    std::array<std::byte, 29> last;
    std::unique_ptr<WavePacketDecoder> decoder;
};

} // namespace

void decode_layered_chunk(const Format& format, std::span<const std::byte> bytes, std::uint64_t count, std::byte* out,
                          ModelStore& store) {
    if (count == 0) return;
    const std::size_t length = format.record_length;
    const std::size_t layers_n = layer_count(format);
    const std::size_t head = length + 4 + 4 * layers_n;
    if (bytes.size() < head)
        throw ChunkError(bytes.size(), "ends inside the chunk header (first record, point count, layer sizes; " +
                                           std::to_string(head) + " bytes)");
    std::memcpy(out, bytes.data(), length);
    const std::uint32_t stored_count = load_le<std::uint32_t>(bytes.data() + length);
    if (stored_count != count)
        throw ChunkError(length, "holds " + std::to_string(stored_count) + " points, but the chunk table says " +
                                     std::to_string(count));
    std::vector<Layer> layers(layers_n);
    std::size_t at = head;
    for (std::size_t i = 0; i < layers_n; ++i) {
        const std::uint32_t size = load_le<std::uint32_t>(bytes.data() + length + 4 + 4 * i);
        if (size > bytes.size() - at)
            throw ChunkError(length + 4 + 4 * i, "layer " + std::to_string(i) + " of " + std::to_string(size) +
                                                     " bytes runs past the chunk's end");
        layers[i].bytes = bytes.subspan(at, size);
        at += size;
    }
    if (count == 1) return;
    for (Layer& layer : layers) {
        layer.present = !layer.bytes.empty();
        layer.dec = layer.present ? ArithmeticDecoder(layer.bytes, store) : ArithmeticDecoder(store);
    }

    // Item decoders in item order; POINT14 is first and sets the channel for the others.
    std::optional<Point14Decoder> point;
    std::optional<Channels<RgbState>> rgb;
    std::optional<Channels<ByteState>> extra;
    std::optional<Channels<WaveState>> wave;
    Layer* rgb_layers = nullptr;
    Layer* byte_layers = nullptr;
    Layer* wave_layer = nullptr;
    std::size_t layer = 0, field = 0, rgb_at = 0, byte_at = 0, byte_size = 0, wave_at = 0;
    bool nir = false;
    for (const Item& item : format.items) {
        const std::byte* first = out + field;
        switch (item.type) {
        case ItemType::point14: point.emplace(first, &layers[layer], item.version); break;
        case ItemType::rgb14:
        case ItemType::rgbnir14: {
            RgbState s;
            s.last = {load_le<std::uint16_t>(first), load_le<std::uint16_t>(first + 2),
                      load_le<std::uint16_t>(first + 4)};
            nir = item.type == ItemType::rgbnir14;
            if (nir) s.nir = load_le<std::uint16_t>(first + 6);
            rgb.emplace(point->context(), std::move(s), item.version);
            rgb_layers = &layers[layer];
            rgb_at = field;
            break;
        }
        case ItemType::byte14: {
            ByteState s = ByteState::from(std::vector<std::uint8_t>(item.size));
            std::memcpy(s.last.data(), first, item.size);
            extra.emplace(point->context(), std::move(s), item.version);
            byte_layers = &layers[layer];
            byte_at = field;
            byte_size = item.size;
            break;
        }
        case ItemType::wavepacket14: {
            WaveState s;
            std::memcpy(s.last.data(), first, 29);
            s.decoder = std::make_unique<WavePacketDecoder>(first, store);
            wave.emplace(point->context(), std::move(s), item.version);
            wave_layer = &layers[layer];
            wave_at = field;
            break;
        }
        default: throw ChunkError(0, "item " + item_name(item.type) + " cannot be layered");
        }
        layer += item.type == ItemType::point14    ? 9
                 : item.type == ItemType::rgbnir14 ? 2
                 : item.type == ItemType::byte14   ? item.size
                                                   : 1;
        field += item.size;
    }

    std::byte* record = out;
    for (std::uint64_t i = 1; i < count; ++i) {
        record += length;
        point->decode(record);
        const std::uint32_t channel = point->context();
        if (rgb) {
            rgb->follow(channel, [](const RgbState& from) {
                RgbState s;
                s.last = from.last;
                s.nir = from.nir;
                return s;
            });
            RgbState& models = rgb->models();
            RgbState& last = rgb->last();
            if (rgb_layers[0].present) decode_rgb(rgb_layers[0].dec, *models.rgb, last.last);
            std::byte* o = record + rgb_at;
            for (int c = 0; c < 3; ++c) store_le(o + 2 * c, last.last[c]);
            if (nir) {
                if (rgb_layers[1].present) {
                    ArithmeticDecoder& dec = rgb_layers[1].dec;
                    const std::uint32_t used = dec.decode_symbol(*models.nir_used);
                    std::uint32_t lo = last.nir & 0xFF, hi = last.nir >> 8;
                    if (used & 1) lo = static_cast<std::uint8_t>(dec.decode_symbol((*models.nir_diff)[0]) + lo);
                    if (used & 2) hi = static_cast<std::uint8_t>(dec.decode_symbol((*models.nir_diff)[1]) + hi);
                    last.nir = static_cast<std::uint16_t>(lo | hi << 8);
                }
                store_le(o + 6, last.nir);
            }
        }
        if (extra) {
            extra->follow(channel, [](const ByteState& from) { return ByteState::from(from.last); });
            ByteState& models = extra->models();
            ByteState& last = extra->last();
            for (std::size_t b = 0; b < byte_size; ++b) {
                if (byte_layers[b].present)
                    last.last[b] =
                        static_cast<std::uint8_t>(last.last[b] + byte_layers[b].dec.decode_symbol(models.models[b]));
                record[byte_at + b] = std::byte{last.last[b]};
            }
        }
        if (wave) {
            wave->follow(channel, [&store](const WaveState& from) {
                WaveState s;
                s.last = from.last;
                s.decoder = std::make_unique<WavePacketDecoder>(from.last.data(), store);
                return s;
            });
            WaveState& models = wave->models();
            WaveState& last = wave->last();
            if (wave_layer->present) {
                models.decoder->decode(wave_layer->dec, last.last.data());
            }
            std::memcpy(record + wave_at, last.last.data(), 29);
        }
    }
    for (std::size_t i = 0; i < layers.size(); ++i)
        if (layers[i].present && layers[i].dec.overrun())
            throw ChunkError(static_cast<std::size_t>(layers[i].bytes.data() - bytes.data()) + layers[i].bytes.size(),
                             "layer " + std::to_string(i) + " ends before its " + std::to_string(count) +
                                 " points are decoded (truncated or corrupt)");
}

} // namespace lasmesh::laz
