// SPDX-License-Identifier: Apache-2.0
// Meshes a LAS file through the installed library's one entry point, build_mesh, twice: with
// BuildOptions{} into DEFAULT_OUT (which must equal the command line's output with no options,
// byte for byte), and as a coarse closed surface whose mesh is checked here; then reads the
// points and the written mesh back and compares them. The headers, the reader (Boost.Iostreams
// inside), the OpenCL accumulation, the extractor (TBB), the writers and readers all link from
// the package alone.
// Usage: consumer INPUT DEFAULT_OUT CLOSED_OUT.ply
#include <lasmesh/build_mesh.hpp>
#include <lasmesh/compare.hpp>
#include <lasmesh/las_reader.hpp>
#include <lasmesh/mesh_files.hpp>

#include <iostream>
#include <map>
#include <utility>
#include <vector>

int main(int argc, char** argv) {
    if (argc != 4) return 1;
    try {
        lasmesh::BuildOptions defaults;
        defaults.outputs.push_back({argv[2]});
        lasmesh::build_mesh(argv[1], defaults);
    } catch (const lasmesh::Error& e) {
        std::cerr << "consumer: " << e.what() << "\n";
        return 1;
    }

    lasmesh::BuildOptions options;
    options.grid = lasmesh::GridRequest::longest(32); // a coarse grid: the test scene is small
    options.surface = lasmesh::SurfaceKind::closed;   // a watertight solid, checked below
    options.outputs.push_back({argv[3], lasmesh::MeshFormat::ply});
    options.keep_mesh = true;
    const lasmesh::BuildResult result = lasmesh::build_mesh(argv[1], options);
    const lasmesh::Mesh& mesh = *result.mesh;

    // Closed: every edge is shared by exactly two triangles, once in each direction.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (const auto& t : mesh.triangles)
        for (int c = 0; c < 3; ++c) ++edges[{t[c], t[(c + 1) % 3]}];
    bool closed = !mesh.triangles.empty();
    for (const auto& [edge, count] : edges)
        closed = closed && count == 1 && edges.count({edge.second, edge.first}) == 1;

    std::cout << result.report.points_read << " points, " << mesh.triangles.size() << " triangles, "
              << (closed ? "closed" : "open") << "\n";

    // The points, read through the public reader; the mesh, read back from its file.
    lasmesh::LasReader reader(argv[1]);
    std::vector<lasmesh::LasPoint> points(4096);
    std::uint64_t read = 0;
    while (const std::size_t n = lasmesh::read_points(reader, points)) read += n;
    const lasmesh::Mesh written = lasmesh::read_mesh(argv[3]);
    lasmesh::LasReader cloud(argv[1]);
    const lasmesh::CompareResult fit = lasmesh::compare(written, cloud, {});
    std::cout << "read " << read << " points; half of them within " << fit.cloud_to_mesh.median << " of the mesh\n";
    if (read != result.report.points_read || written.triangles.size() != mesh.triangles.size()) return 1;
    const bool counts_agree = result.report.triangles == mesh.triangles.size() &&
                              result.report.vertices == mesh.positions.size() && result.report.outputs.size() == 1;
    return closed && counts_agree ? 0 : 1;
}
