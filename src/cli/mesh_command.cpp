// The pipeline behind `lasmesh INPUT -o OUT.ply`, timed per stage.
#include "mesh_command.hpp"

#include "lasmesh/error.hpp"
#include "lasmesh/marching_cubes.hpp"
#include "lasmesh/mesh_pieces.hpp"
#include "lasmesh/output_file.hpp"
#include "lasmesh/ply_writer.hpp"
#include "json_writer.hpp"

#include <tbb/global_control.h>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <optional>

namespace lasmesh::cli {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

} // namespace

void add_mesh_options(CLI::App& app, MeshOptions& o) {
    app.add_option("INPUT", o.input, "LAS file, or - for standard input (gzip, bzip2, xz, zstd recognised)");
    app.add_option("-o,--output", o.outputs, "Output mesh: .ply (binary; --ascii for text)");
    add_grid_options(app, o.grid);
    app.add_option("--iso", o.iso, "Points per cell at the surface (cells with more are inside), or auto")
        ->capture_default_str();
    app.add_option("--placement", o.placement,
                   "Vertices on the scanned surface (surface) or on the iso level set as in classic "
                   "marching cubes (iso)")
        ->capture_default_str();
    app.add_option("--min-piece", o.min_piece,
                   "Remove isolated pieces smaller than this bounding-box diagonal: a percentage of the "
                   "whole mesh's diagonal (5%), a length in the file's units, or 0 to keep all")
        ->capture_default_str();
    app.add_flag("--ascii", o.ascii, "Write ASCII PLY instead of binary");
    app.add_option("--threads", o.threads, "Threads for extraction (default: all cores)")->check(CLI::Range(1, 1024));
}

void run_mesh(const MeshOptions& o, std::ostream& summary) {
    if (o.outputs.empty()) throw Error(ErrorKind::usage, "no output: give -o OUT.ply");
    for (const std::string& path : o.outputs) {
        if (extension(path) != ".ply")
            throw Error(ErrorKind::usage, "-o \"" + path + "\": unknown output extension, expected .ply");
        check_output_folder(path); // before reading: nobody should wait to learn this
    }
    const AccumulateOptions accumulate = accumulate_options(o.grid);
    const double requested_iso = parse_iso(o.iso);
    const MinPiece min_piece = parse_min_piece(o.min_piece);
    const VertexPlacement placement = parse_placement(o.placement);
    std::optional<tbb::global_control> thread_limit;
    if (o.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, o.threads);

    const auto start = std::chrono::steady_clock::now();
    LasReader reader(o.input);
    ComputeDevice device(o.grid.device);
    const DensityGrid grid = accumulate_density(reader, device, accumulate);
    const double t_accumulate = seconds_since(start);

    const auto extract_start = std::chrono::steady_clock::now();
    const double iso = requested_iso < 0 ? automatic_iso(grid) : requested_iso;
    Mesh mesh = extract_isosurface(grid, iso, placement);
    const PieceCount pieces = remove_small_pieces(mesh, min_piece);
    const double t_extract = seconds_since(extract_start);

    const auto write_start = std::chrono::steady_clock::now();
    for (const std::string& path : o.outputs) write_ply(mesh, path, o.ascii);
    const double t_write = seconds_since(write_start);

    const auto& s = grid.spec;
    summary << std::setprecision(6) << "input          " << reader.stream().name() << "\n"
            << "device         " << device.info().name << "\n"
            << "points         " << grid.points_read << " read, " << grid.points_outside << " outside the grid\n"
            << "grid           " << s.dims[0] << " x " << s.dims[1] << " x " << s.dims[2] << " cells of "
            << format_double(s.cell_size) << "\n"
            << "iso            " << format_double(iso) << (requested_iso < 0 ? " (auto)" : "")
            << " points per cell, vertices placed on the " << (placement == VertexPlacement::iso ? "iso level" : "surface")
            << "\n"
            << "origin         " << format_double(mesh.origin[0]) << " " << format_double(mesh.origin[1]) << " "
            << format_double(mesh.origin[2]) << " (PLY positions are relative to it)\n"
            << "pieces         " << pieces.pieces << " connected, " << pieces.removed << " removed ("
            << pieces.triangles_removed << " triangles) below a diagonal of " << format_double(pieces.min_diagonal)
            << (min_piece.relative ? " (" + o.min_piece + " of the mesh's)" : std::string()) << "\n"
            << "mesh           " << mesh.positions.size() << " vertices, " << mesh.triangles.size() << " triangles"
            << (mesh.colors.empty() ? ", no colour" : ", coloured") << "\n";
    for (const std::string& path : o.outputs)
        summary << "output         " << path << " (" << std::filesystem::file_size(path) << " bytes)\n";
    summary << std::fixed << std::setprecision(3) << "seconds        read+accumulate " << t_accumulate << ", extract "
            << t_extract << ", write " << t_write << ", total " << seconds_since(start) << "\n";
}

} // namespace lasmesh::cli
