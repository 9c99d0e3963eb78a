// The pipeline behind `lasmesh INPUT -o OUT.ply`, timed per stage and per output.
#include "mesh_command.hpp"

#include "lasmesh/draco_writer.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/gltf_writer.hpp"
#include "lasmesh/marching_cubes.hpp"
#include "lasmesh/mesh_pieces.hpp"
#include "lasmesh/output_file.hpp"
#include "lasmesh/ply_writer.hpp"
#include "json_writer.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <sstream>

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

bool is_draco(const std::string& path) { return extension(path) == ".drc" || extension(path) == ".glb"; }

// Two significant digits: enough to judge a quantization step against a cell.
std::string two_digits(double value) {
    std::ostringstream text;
    text << std::setprecision(2) << value;
    return text.str();
}

void write_output(const Mesh& mesh, const std::string& path, const MeshOptions& o) {
    const std::string ext = extension(path);
    if (ext == ".drc") write_draco(mesh, path, o.draco);
    else if (ext == ".glb") write_glb(mesh, path, o.draco);
    else write_ply(mesh, path, o.ascii);
}

} // namespace

void add_mesh_options(CLI::App& app, MeshOptions& o) {
    app.add_option("INPUT", o.input, "LAS file, or - for standard input (gzip, bzip2, xz, zstd recognised)");
    app.add_option("-o,--output", o.outputs,
                   "Output mesh, repeatable; the extension sets the format: .ply (binary; --ascii for text), "
                   ".drc (Draco), .glb (glTF 2.0 binary, Draco-compressed)");
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
    app.add_option("--draco-bits", o.draco.position_bits,
                   "Position quantization of .drc and .glb, in bits (default: the fewest whose step is at most a "
                   "tenth of a cell, 8 to 16)")
        ->check(CLI::Range(1, 30));
    app.add_option("--draco-level", o.draco.level, "Draco compression level, 0 (fastest) to 10 (smallest)")
        ->capture_default_str()
        ->check(CLI::Range(0, 10));
    app.add_option("--threads", o.threads, "Threads for extraction (default: all cores)")->check(CLI::Range(1, 1024));
}

void run_mesh(const MeshOptions& o, std::ostream& summary) {
    if (o.outputs.empty()) throw Error(ErrorKind::usage, "no output: give -o OUT.ply, OUT.drc or OUT.glb");
    for (const std::string& path : o.outputs) {
        if (extension(path) != ".ply" && !is_draco(path))
            throw Error(ErrorKind::usage, "-o \"" + path + "\": unknown output extension, expected .ply, .drc or .glb");
        check_output_folder(path); // before reading: nobody should wait to learn this
    }
    AccumulateOptions accumulate = accumulate_options(o.grid);
    const double requested_iso = parse_iso(o.iso);
    const MinPiece min_piece = parse_min_piece(o.min_piece);
    const VertexPlacement placement = parse_placement(o.placement);
    std::optional<tbb::global_control> thread_limit;
    if (o.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, o.threads);

    const auto start = std::chrono::steady_clock::now();
    if (o.grid.scan_bounds) accumulate.bounds = scan_bounds(o.input);
    LasReader reader(o.input);
    // An empty mesh is no use and Draco cannot encode one: say so before any device work.
    if (reader.header().point_count == 0)
        throw_input_error(reader.stream().name(), "the header promises no point records (point count 0): nothing to mesh");
    ComputeDevice device(o.grid.device);
    const DensityGrid grid = accumulate_density(reader, device, accumulate);
    summary << outside_advice(grid.points_outside, grid.points_read);
    const double t_accumulate = seconds_since(start);

    const auto extract_start = std::chrono::steady_clock::now();
    const double iso = requested_iso < 0 ? automatic_iso(grid) : requested_iso;
    Mesh mesh = extract_isosurface(grid, iso, placement);
    const PieceCount pieces = remove_small_pieces(mesh, min_piece);
    const double t_extract = seconds_since(extract_start);

    const auto write_start = std::chrono::steady_clock::now();
    std::vector<double> t_outputs;
    for (const std::string& path : o.outputs) {
        const auto output_start = std::chrono::steady_clock::now();
        write_output(mesh, path, o);
        t_outputs.push_back(seconds_since(output_start));
    }
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
            << format_double(mesh.origin[2]) << " (output positions are relative to it)\n"
            << "pieces         " << pieces.pieces << " connected, " << pieces.removed << " removed ("
            << pieces.triangles_removed << " triangles) below a diagonal of " << format_double(pieces.min_diagonal)
            << (min_piece.relative ? " (" + o.min_piece + " of the mesh's)" : std::string()) << "\n"
            << "mesh           " << mesh.positions.size() << " vertices, " << mesh.triangles.size() << " triangles"
            << (mesh.colors.empty() ? ", no colour" : ", coloured") << "\n";
    if (std::any_of(o.outputs.begin(), o.outputs.end(), is_draco)) {
        const int bits = position_bits(mesh, o.draco);
        summary << "draco          " << bits << " bits" << (o.draco.position_bits == 0 ? " (auto)" : "")
                << " position quantization, step " << two_digits(quantization_step(mesh, bits));
        if (mesh.cell_size > 0) summary << " (a tenth of a cell is " << two_digits(mesh.cell_size / 10) << ")";
        summary << ", level " << o.draco.level << "\n";
    }
    for (const std::string& path : o.outputs)
        summary << "output         " << path << " (" << std::filesystem::file_size(path) << " bytes)\n";
    summary << std::fixed << std::setprecision(3) << "seconds        read+accumulate " << t_accumulate << ", extract "
            << t_extract << ", write " << t_write << " (";
    for (std::size_t i = 0; i < o.outputs.size(); ++i)
        summary << (i ? ", " : "") << extension(o.outputs[i]).substr(1) << " " << t_outputs[i];
    summary << "), total " << seconds_since(start) << "\n";
}

} // namespace lasmesh::cli
