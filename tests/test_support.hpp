// SPDX-License-Identifier: Apache-2.0
// Helpers shared by the tests: temporary folders, whole-file I/O, generated LAS bytes.
#pragma once

#include "lasgen/las_writer.hpp"
#include "lasgen/scene.hpp"

#include <boost/iostreams/copy.hpp>
#include <boost/iostreams/filtering_stream.hpp>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace test {

using Bytes = std::vector<std::byte>;

// The message of the lasmesh::Error `call` throws; the test fails when it throws none.
std::string error_text(const std::function<void()>& call);

// Whether `part` occurs in `text`.
bool contains(const std::string& text, const std::string& part);

// A fresh folder under the system temp folder, removed with everything in it at scope exit.
class TempDir {
  public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::filesystem::path path() const { return path_; }
    std::string file(const std::string& name) const { return (path_ / name).string(); }

  private:
    std::filesystem::path path_;
};

Bytes read_file(const std::string& path);

// `plain` through a Boost.Iostreams compressor (gzip_compressor(), zstd_compressor(), ...).
template <typename Compressor>
Bytes compress(const Bytes& plain, Compressor compressor) {
    std::istringstream source(std::string(reinterpret_cast<const char*>(plain.data()), plain.size()));
    std::ostringstream sink;
    boost::iostreams::filtering_ostream out;
    out.push(compressor);
    out.push(sink);
    boost::iostreams::copy(source, out);
    const std::string text = sink.str();
    Bytes bytes(text.size());
    std::memcpy(bytes.data(), text.data(), text.size());
    return bytes;
}
void write_file(const std::string& path, const Bytes& bytes);

// A whole LAS file of `count` points of `scene`, as lasgen would write it.
Bytes make_las(const lasgen::LasLayout& layout, const lasgen::Scene& scene, std::uint64_t count,
               std::uint64_t seed = 1);

// Points [first, first + count) of `scene` as make_las numbers them, in `layout` with its own
// scale and offset (a file of a survey); the header bounds are the scene's.
Bytes make_las_part(const lasgen::LasLayout& layout, const lasgen::Scene& scene, std::uint64_t first,
                    std::uint64_t count, std::uint64_t seed = 1);

// The JSON chunk of a binary glTF file (.glb).
std::string glb_json(const std::string& glb);

// The shared LAS test corpus beside the checkout, or empty when it is absent.
std::filesystem::path shared_las_folder();

} // namespace test

// The sparse grid as dense per-cell arrays (cell index as in GridSpec: x fastest), so tests can
// compare whole grids and address cells by index.
#include "grid/cell_sums.hpp"

namespace test {

struct DenseGrid {
    const lasmesh::CellGrid* grid = nullptr; // the grid it was made from: keep it alive
    std::vector<std::uint64_t> count, red, green, blue;
    lasmesh::Rgb8 mean_color(std::uint64_t cell) const;
};
DenseGrid dense(const lasmesh::CellGrid& grid);

// A sparse grid holding the given per-cell counts (and colour sums when `red` is not empty),
// every cell's points at its centre; for extraction tests that need no device.
lasmesh::CellGrid grid_from_counts(const lasmesh::GridSpec& spec, const std::vector<std::uint64_t>& count,
                                   const std::vector<std::uint64_t>& red = {},
                                   const std::vector<std::uint64_t>& green = {},
                                   const std::vector<std::uint64_t>& blue = {}, std::uint32_t color_max_word = 255);

// Per-cell counts and colour sums written as dense arrays (x fastest), turned into the sparse
// grid where a CellGrid is expected.
struct DenseCells {
    lasmesh::GridSpec spec;
    std::vector<std::uint64_t> count, red, green, blue;
    std::uint32_t color_max_word = 255;
    operator lasmesh::CellGrid() const { return grid_from_counts(spec, count, red, green, blue, color_max_word); }
};

// One OpenCL device (the default) for the whole test run.
lasmesh::ComputeDevice& device();

// A LAS 1.2 format-3 file (format 1 without colour) holding exactly `points`.
Bytes las_with_points(const std::vector<lasgen::GeneratedPoint>& points, const lasmesh::Vec3& min,
                      const lasmesh::Vec3& max, int color_bits = 8, int format = 3, double scale = 0.01);

// Every record of the LAS file at `path` accumulated on device().
lasmesh::CellGrid accumulate_file(const std::string& path, lasmesh::AccumulateOptions options = {});

// A manifest of measured facts (../shared/data/*/MANIFEST.tsv): one row per file, by column name.
using Row = std::map<std::string, std::string>;
std::vector<Row> read_manifest(const std::filesystem::path& folder);
std::vector<std::string> split(const std::string& text, char separator);

} // namespace test

// Distances between two surfaces, worked out here and not with the library's measure/ code, so a
// test of the simplifier does not trust what it could share a mistake with.
#include "lasmesh/mesh.hpp"

namespace test {

// Points on every triangle of `mesh` (in its local frame) no farther than `spacing` apart: its
// corners, and a barycentric lattice fine enough for its longest edge (at most 12 steps an edge).
std::vector<lasmesh::Vec3> dense_samples(const lasmesh::Mesh& mesh, double spacing);

// The largest distance from one of `points` to the nearest triangle of `surface`, looking only
// `window` around each point: +infinity when some point has no triangle that near.
double farthest_from(const lasmesh::Mesh& surface, const std::vector<lasmesh::Vec3>& points, double window);

} // namespace test
