// scan_points: min/max over raw integers (cheap), converted to world units once at the end.
#include "lasmesh/read/las_scan.hpp"

#include <algorithm>
#include <limits>
#include <vector>

namespace lasmesh {

ScanResult scan_points(LasReader& reader, std::size_t chunk_records) {
    const PointDecoder decoder(reader.header());
    const std::size_t length = decoder.record_length;
    // Bounded in bytes too: 65,536 records of a 65,535-byte record length would be 4 GB.
    constexpr std::size_t max_chunk_bytes = std::size_t{16} << 20;
    const std::size_t records = std::clamp<std::size_t>(chunk_records, 1, std::max<std::size_t>(1, max_chunk_bytes / length));
    std::vector<std::byte> chunk(records * length);

    RawXYZ raw_min;
    RawXYZ raw_max;
    raw_min.fill(std::numeric_limits<std::int32_t>::max());
    raw_max.fill(std::numeric_limits<std::int32_t>::min());
    Rgb16 color_min{0xFFFF, 0xFFFF, 0xFFFF};
    Rgb16 color_max{0, 0, 0};

    ScanResult result;
    result.has_color = decoder.has_color();
    while (std::size_t count = reader.read_records(chunk)) {
        const std::byte* record = chunk.data();
        for (std::size_t i = 0; i < count; ++i, record += length) {
            RawXYZ raw = PointDecoder::raw_xyz(record);
            for (int a = 0; a < 3; ++a) {
                raw_min[a] = std::min(raw_min[a], raw[a]);
                raw_max[a] = std::max(raw_max[a], raw[a]);
            }
            if (result.has_color) {
                Rgb16 c = decoder.color(record);
                for (int a = 0; a < 3; ++a) {
                    color_min[a] = std::min(color_min[a], c[a]);
                    color_max[a] = std::max(color_max[a], c[a]);
                }
            }
        }
        result.point_count += count;
    }
    if (result.point_count == 0) return result;
    for (int a = 0; a < 3; ++a) { // scales are positive (checked with the header)
        result.min[a] = decoder.to_world(a, raw_min[a]);
        result.max[a] = decoder.to_world(a, raw_max[a]);
    }
    if (result.has_color) {
        result.color_min = color_min;
        result.color_max = color_max;
    }
    return result;
}

} // namespace lasmesh
