// SPDX-License-Identifier: Apache-2.0
// LAZ decoding throughput: decodes FILE's records REPEAT times through LasReader with at most
// THREADS TBB threads and prints points per second. Small corpus files are repeated to get a
// measurable run; chunks are decoded in parallel within each pass.
// Usage: laz_bench FILE THREADS REPEAT
#include "lasmesh/las_reader.hpp"

#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: laz_bench FILE THREADS REPEAT\n");
        return 1;
    }
    const int threads = std::atoi(argv[2]);
    const int repeat = std::atoi(argv[3]);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    std::uint64_t points = 0;
    double best = 1e300, best_cpu = 1e300;
    for (int round = 0; round < 3; ++round) { // best of 3
        const auto start = std::chrono::steady_clock::now();
        const std::clock_t cpu_start = std::clock(); // all threads' CPU time: the per-core rate under load
        points = 0;
        for (int r = 0; r < repeat; ++r) {
            lasmesh::LasReader reader(argv[1]);
            std::vector<std::byte> buffer(std::size_t{reader.header().point_record_length} << 16);
            while (std::size_t n = reader.read_records(buffer)) points += n;
        }
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        best_cpu = std::min(best_cpu, static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
    }
    std::printf("%s threads=%d points=%llu wall_s=%.3f Mpoints/s=%.2f cpu_s=%.3f Mpoints/cpu-s=%.2f\n", argv[1],
                threads, static_cast<unsigned long long>(points), best, points / best / 1e6, best_cpu,
                points / best_cpu / 1e6);
}
