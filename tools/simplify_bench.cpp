// SPDX-License-Identifier: Apache-2.0
// simplify_bench: simplifies a PLY mesh (as lasmesh writes it with --simplify 0) to an error
// bound and reports what the simplification did (tools/bench_simplify.sh): triangles, seconds,
// CPU seconds, faces turned over against the original surface, edges that became non-manifold,
// zero-area faces, and the distance between the two surfaces both ways (sampled), in cells.
//
// Usage: simplify_bench MESH.ply ERROR_IN_CELLS [--threads N] [--runs N] [--lock-border] [--time-only] [-o OUT.ply]
// (--time-only: triangles and seconds, no checks; --runs N: the best of N runs' times)
#include "io/ply_reader.hpp"
#include "io/ply_writer.hpp"
#include "lasmesh/normals.hpp"
#include "lasmesh/simplify.hpp"
#include "measure/mesh_distance.hpp"
#include "mesh/simplify_check.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <map>
#include <memory>
#include <string>

using namespace lasmesh;

namespace {

double cpu_seconds() {
    return double(std::clock()) / CLOCKS_PER_SEC;
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    const std::size_t k = std::min(v.size() - 1, std::size_t(q * double(v.size())));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: simplify_bench MESH.ply ERROR_IN_CELLS [--threads N] [--runs N] [--lock-border] "
                             "[--time-only] [-o OUT.ply]\n");
        return 1;
    }
    const std::string path = argv[1];
    const double cells = std::atof(argv[2]);
    int threads = 0, runs = 1;
    bool lock = false, time_only = false;
    std::string out;
    for (int i = 3; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--threads" && i + 1 < argc)
            threads = std::atoi(argv[++i]);
        else if (a == "--runs" && i + 1 < argc)
            runs = std::atoi(argv[++i]);
        else if (a == "--lock-border")
            lock = true;
        else if (a == "--time-only")
            time_only = true;
        else if (a == "-o" && i + 1 < argc)
            out = argv[++i];
    }
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);

    const Mesh original = read_ply(path);
    const double cell = original.cell_size > 0 ? original.cell_size : 1;
    SimplifyOptions options;
    options.error = cells * cell;
    options.lock_border = lock;

    Mesh m;
    SimplifyReport report;
    double best_wall = 1e30, best_cpu = 1e30;
    for (int r = 0; r < runs; ++r) {
        m = original;
        const double c0 = cpu_seconds();
        const auto t0 = std::chrono::steady_clock::now();
        report = simplify_mesh(m, options);
        best_wall = std::min(best_wall, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        best_cpu = std::min(best_cpu, cpu_seconds() - c0);
    }
    if (time_only) {
        std::printf("{\"triangles_before\": %zu, \"triangles_after\": %zu, \"seconds\": %.3f, \"cpu_seconds\": %.3f}\n",
                    report.triangles_before, report.triangles_after, best_wall, best_cpu);
        return 0;
    }
    const SimplifyCheck check = check_simplified(original, m);
    const TriangleSearch before(original), after(m);
    std::vector<double> there, back;
    Vec3 worst{};
    double farthest = -1;
    for (const Vec3& p : sample_surface(m, 200000)) {
        there.push_back(before.distance(p) / cell);
        if (there.back() > farthest) farthest = there.back(), worst = p;
    }
    if (std::getenv("SIMPLIFY_BENCH_WORST"))
        std::fprintf(stderr, "farthest from the original: %g %g %g\n", worst[0], worst[1], worst[2]);
    Vec3 worst_back{};
    farthest = -1;
    for (const Vec3& p : sample_surface(original, 200000)) {
        back.push_back(after.distance(p) / cell);
        if (back.back() > farthest) farthest = back.back(), worst_back = p;
    }
    if (std::getenv("SIMPLIFY_BENCH_WORST"))
        std::fprintf(stderr, "original farthest from the simplified: %g %g %g\n", worst_back[0], worst_back[1],
                     worst_back[2]);
    std::printf("{\"triangles_before\": %zu, \"triangles_after\": %zu, \"error_cells\": %g, \"seconds\": %.3f, "
                "\"cpu_seconds\": %.3f, \"triangles_per_second\": %.0f, \"flipped\": %zu, \"new_bad_edges\": %zu, "
                "\"zero_area\": %zu, \"zero_area_before\": %zu, \"simplified_to_original_max\": %.3f, "
                "\"simplified_to_original_p99\": %.3f, \"original_to_simplified_max\": %.3f, "
                "\"original_to_simplified_p99\": %.3f}\n",
                report.triangles_before, report.triangles_after, cells, best_wall, best_cpu,
                double(report.triangles_before) / best_wall, check.flipped, check.bad_edges - check.bad_edges_before,
                check.zero_area, check.zero_area_before, quantile(there, 1.0), quantile(there, 0.99),
                quantile(back, 1.0), quantile(back, 0.99));
    if (!out.empty()) {
        write_ply(m, out);
    }
    return 0;
}
