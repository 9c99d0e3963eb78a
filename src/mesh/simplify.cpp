// Simplification with meshoptimizer (Debian's libmeshoptimizer-dev, 0.18). Its error is relative
// to the mesh extent (meshopt_simplifyScale), so the bound in file units is divided by that scale.
#include "lasmesh/mesh/simplify.hpp"

#include <meshoptimizer.h>

#include <chrono>
#include <limits>

namespace lasmesh {

namespace {

// Drops the vertices no triangle uses and renumbers the rest in their old order.
void remove_unused_vertices(Mesh& mesh) {
    constexpr std::uint32_t unused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> remap(mesh.positions.size(), unused);
    for (const auto& t : mesh.triangles)
        for (const std::uint32_t v : t) remap[v] = 0;
    std::uint32_t kept = 0;
    for (std::size_t v = 0; v < remap.size(); ++v) {
        if (remap[v] == unused) continue;
        remap[v] = kept;
        mesh.positions[kept] = mesh.positions[v];
        if (!mesh.colors.empty()) mesh.colors[kept] = mesh.colors[v];
        if (!mesh.normals.empty()) mesh.normals[kept] = mesh.normals[v];
        ++kept;
    }
    mesh.positions.resize(kept);
    if (!mesh.colors.empty()) mesh.colors.resize(kept);
    if (!mesh.normals.empty()) mesh.normals.resize(kept);
    for (auto& t : mesh.triangles)
        for (std::uint32_t& v : t) v = remap[v];
}

} // namespace

SimplifyReport simplify_mesh(Mesh& mesh, const SimplifyOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    SimplifyReport report;
    report.triangles_before = report.triangles_after = mesh.triangles.size();
    report.error = options.error;
    if (!(options.error > 0) || mesh.triangles.empty()) return report;

    const float* positions = mesh.positions[0].data();
    const std::size_t stride = sizeof mesh.positions[0];
    const float scale = meshopt_simplifyScale(positions, mesh.positions.size(), stride);
    if (!(scale > 0)) return report;
    const auto* indices = mesh.triangles[0].data();
    const std::size_t index_count = 3 * mesh.triangles.size();
    std::vector<unsigned int> out(index_count);
    float result_error = 0;
    // Target 0 triangles: only the error bound stops the collapses.
    const std::size_t kept = meshopt_simplify(out.data(), indices, index_count, positions, mesh.positions.size(), stride, 0,
                                              static_cast<float>(options.error / scale),
                                              options.lock_border ? meshopt_SimplifyLockBorder : 0, &result_error);
    mesh.triangles.resize(kept / 3);
    for (std::size_t t = 0; t < kept / 3; ++t) mesh.triangles[t] = {out[3 * t], out[3 * t + 1], out[3 * t + 2]};
    remove_unused_vertices(mesh);

    report.triangles_after = mesh.triangles.size();
    report.result_error = double(result_error) * scale;
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

} // namespace lasmesh
