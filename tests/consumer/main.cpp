// Reads a LAS file through the installed library and meshes a grid built on the host: the
// headers, the reader (Boost.Iostreams inside), the extractor (TBB) and the PLY writer link.
#include <lasmesh/read/las_point.hpp>
#include <lasmesh/read/las_reader.hpp>
#include <lasmesh/mesh/marching_cubes.hpp>
#include <lasmesh/io/ply_writer.hpp>

#include <cmath>
#include <iostream>
#include <vector>

int main(int argc, char** argv) {
    if (argc != 3) return 1;
    lasmesh::LasReader reader(argv[1]);
    const lasmesh::PointDecoder decoder(reader.header());
    lasmesh::DensityGrid grid;
    grid.spec.dims = {16, 16, 16};
    grid.spec.origin = reader.header().min;
    grid.spec.cell_size = (reader.header().max[0] - reader.header().min[0]) / 15.99;
    grid.count.assign(grid.spec.cell_count(), 0);
    std::vector<std::byte> chunk(4096 * decoder.record_length);
    while (std::size_t n = reader.read_records(chunk))
        for (std::size_t r = 0; r < n; ++r) {
            const lasmesh::Vec3 p = decoder.position(chunk.data() + r * decoder.record_length);
            std::uint64_t cell = 0;
            for (int a = 2; a >= 0; --a) {
                const auto i = static_cast<std::uint64_t>((p[a] - grid.spec.origin[a]) / grid.spec.cell_size);
                cell = cell * 16 + std::min<std::uint64_t>(i, 15);
            }
            ++grid.count[cell];
        }
    const lasmesh::Mesh mesh = lasmesh::extract_isosurface(grid, 0.5);
    lasmesh::write_ply(mesh, argv[2], false);
    std::cout << reader.records_read() << " points, " << mesh.triangles.size() << " triangles\n";
    return mesh.triangles.empty() ? 1 : 0;
}
