// SPDX-License-Identifier: Apache-2.0
// scan_points: min/max over raw integers (cheap), converted to world units once at the end; the
// cores scan one chunk while the next is read.
#include "read/las_scan.hpp"

#include "lasmesh/error.hpp"

#include <filesystem>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

namespace lasmesh {

namespace {

// The extremes of the coordinates and colours of some records; merged in any order.
struct Extremes {
    RawXYZ raw_min, raw_max;
    Rgb16 color_min{0xFFFF, 0xFFFF, 0xFFFF}, color_max{0, 0, 0};

    Extremes() {
        raw_min.fill(std::numeric_limits<std::int32_t>::max());
        raw_max.fill(std::numeric_limits<std::int32_t>::min());
    }
    void add(const PointDecoder& decoder, const std::byte* record, std::size_t count) {
        const std::size_t length = decoder.record_length;
        for (std::size_t i = 0; i < count; ++i, record += length) {
            const RawXYZ raw = PointDecoder::raw_xyz(record);
            for (int a = 0; a < 3; ++a) {
                raw_min[a] = std::min(raw_min[a], raw[a]);
                raw_max[a] = std::max(raw_max[a], raw[a]);
            }
            if (decoder.has_color()) {
                const Rgb16 c = decoder.color(record);
                for (int a = 0; a < 3; ++a) {
                    color_min[a] = std::min(color_min[a], c[a]);
                    color_max[a] = std::max(color_max[a], c[a]);
                }
            }
        }
    }
    void merge(const Extremes& o) {
        for (int a = 0; a < 3; ++a) {
            raw_min[a] = std::min(raw_min[a], o.raw_min[a]), raw_max[a] = std::max(raw_max[a], o.raw_max[a]);
            color_min[a] = std::min(color_min[a], o.color_min[a]),
            color_max[a] = std::max(color_max[a], o.color_max[a]);
        }
    }
};

// The extremes of `count` records, split over the cores.
Extremes scan_chunk(const PointDecoder& decoder, const std::byte* records, std::size_t count) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, count, 16384), Extremes{},
        [&](const tbb::blocked_range<std::size_t>& r, Extremes e) {
            e.add(decoder, records + r.begin() * decoder.record_length, r.size());
            return e;
        },
        [](Extremes a, const Extremes& b) {
            a.merge(b);
            return a;
        });
}

} // namespace

ScanResult scan_points(LasReader& reader, std::size_t chunk_records) {
    const PointDecoder decoder(reader.header());
    const std::size_t length = decoder.record_length;
    // Bounded in bytes too: 65,536 records of a 65,535-byte record length would be 4 GB.
    constexpr std::size_t max_chunk_bytes = std::size_t{16} << 20;
    const std::size_t records =
        std::clamp<std::size_t>(chunk_records, 1, std::max<std::size_t>(1, max_chunk_bytes / length));
    // Two chunks: the next is read while the cores scan the current one.
    std::array<std::vector<std::byte>, 2> chunks;
    for (auto& chunk : chunks) chunk.resize(records * length);

    ScanResult result;
    result.has_color = decoder.has_color();
    Extremes all;
    tbb::task_group scanning;
    for (std::size_t k = 0;; ++k) {
        std::vector<std::byte>& chunk = chunks[k % 2];
        std::size_t count = 0;
        try {
            count = reader.read_records(chunk);
        } catch (...) {
            scanning.wait();
            throw;
        }
        scanning.wait();
        if (count == 0) break;
        result.point_count += count;
        scanning.run([&, count] { all.merge(scan_chunk(decoder, chunk.data(), count)); });
    }
    if (result.point_count == 0) return result;
    for (int a = 0; a < 3; ++a) { // scales are positive (checked with the header)
        result.min[a] = decoder.to_world(a, all.raw_min[a]);
        result.max[a] = decoder.to_world(a, all.raw_max[a]);
    }
    if (result.has_color) {
        result.color_min = all.color_min;
        result.color_max = all.color_max;
    }
    return result;
}

void check_rereadable(const std::string& input) {
    if (input == "-" || !std::filesystem::is_regular_file(input))
        throw Error(ErrorKind::usage,
                    "scanning the bounds reads the input twice, so it needs a regular file, not \"" + input +
                        "\": save the stream to a file, or give the bounds",
                    "scan_bounds");
}

ScanResult scan_file(const std::string& input) {
    check_rereadable(input);
    LasReader reader(input);
    return scan_points(reader);
}

} // namespace lasmesh
