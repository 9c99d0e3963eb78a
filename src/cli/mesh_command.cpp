// The pipeline behind `lasmesh INPUT -o OUT.ply`, timed per stage and per output.
#include "mesh_command.hpp"

#include "lasmesh/io/draco_writer.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/io/gltf_writer.hpp"
#include "lasmesh/mesh/marching_cubes.hpp"
#include "lasmesh/mesh/mesh_pieces.hpp"
#include "lasmesh/io/output_file.hpp"
#include "lasmesh/io/ply_writer.hpp"
#include "json_writer.hpp"
#include "progress.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <sstream>

#include <sys/resource.h>

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
    app.add_option("--report", o.report, "Also write the summary as JSON to this file (for pipelines)");
    app.add_flag("-q,--quiet", o.quiet, "No progress line and no summary; errors only");
    app.add_flag("-v,--verbose", o.verbose, "Details of each stage as it ends");
}

namespace {

// Everything the summary and the JSON report tell, gathered as the run goes.
struct RunReport {
    std::string input, device;
    std::uint64_t points_read = 0, points_outside = 0;
    GridSpec grid;
    double iso = 0;
    bool iso_auto = false;
    VertexPlacement placement = VertexPlacement::surface;
    PieceCount pieces;
    std::size_t vertices = 0, triangles = 0;
    bool colored = false;
    Vec3 origin{};
    std::vector<std::pair<std::string, std::uint64_t>> outputs; // path, bytes
    std::vector<double> output_seconds;
    double read_accumulate = 0, extract = 0, write = 0, total = 0;
    std::uint64_t peak_rss_bytes = 0;
};

std::uint64_t peak_rss_bytes() {
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024; // Linux reports kilobytes
}

std::string megabytes(std::uint64_t bytes) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << bytes / 1e6 << " MB";
    return text.str();
}

void write_report_json(const RunReport& r, const std::string& path) {
    JsonWriter json;
    json.begin_object();
    json.key("input").value(r.input);
    json.key("device").value(r.device);
    json.key("points_read").value(r.points_read).key("points_outside").value(r.points_outside);
    json.key("grid").begin_object();
    json.key("dims").array(r.grid.dims).key("cell_size").value(r.grid.cell_size).key("origin").array(r.grid.origin);
    json.end_object();
    json.key("iso").value(r.iso).key("iso_auto").value(r.iso_auto);
    json.key("placement").value(r.placement == VertexPlacement::iso ? "iso" : "surface");
    json.key("pieces").begin_object();
    json.key("connected").value(std::uint64_t{r.pieces.pieces}).key("removed").value(std::uint64_t{r.pieces.removed});
    json.key("min_diagonal").value(r.pieces.min_diagonal).end_object();
    json.key("vertices").value(std::uint64_t{r.vertices}).key("triangles").value(std::uint64_t{r.triangles});
    json.key("colored").value(r.colored);
    json.key("origin").array(r.origin);
    json.key("outputs").begin_array();
    for (std::size_t i = 0; i < r.outputs.size(); ++i)
        json.begin_object()
            .key("path").value(r.outputs[i].first)
            .key("bytes").value(r.outputs[i].second)
            .key("seconds").value(r.output_seconds[i])
            .end_object();
    json.end_array();
    json.key("seconds").begin_object();
    json.key("read_accumulate").value(r.read_accumulate).key("extract").value(r.extract);
    json.key("write").value(r.write).key("total").value(r.total).end_object();
    json.key("peak_rss_bytes").value(r.peak_rss_bytes);
    json.end_object();
    OutputFile out(path);
    out.write(json.str() + "\n");
    out.commit();
}

void print_summary(const RunReport& r, const MeshOptions& o, const Mesh& mesh, std::ostream& summary) {
    const auto& s = r.grid;
    summary << std::setprecision(6) << "input          " << r.input << "\n"
            << "device         " << r.device << "\n"
            << "points         " << r.points_read << " read, " << r.points_outside << " outside the grid\n"
            << "grid           " << s.dims[0] << " x " << s.dims[1] << " x " << s.dims[2] << " cells of "
            << format_double(s.cell_size) << "\n"
            << "iso            " << format_double(r.iso) << (r.iso_auto ? " (auto)" : "")
            << " points per cell, vertices placed on the "
            << (r.placement == VertexPlacement::iso ? "iso level" : "surface") << "\n"
            << "origin         " << format_double(r.origin[0]) << " " << format_double(r.origin[1]) << " "
            << format_double(r.origin[2]) << " (output positions are relative to it)\n"
            << "pieces         " << r.pieces.pieces << " connected, " << r.pieces.removed << " removed ("
            << r.pieces.triangles_removed << " triangles) below a diagonal of " << format_double(r.pieces.min_diagonal)
            << (parse_min_piece(o.min_piece).relative ? " (" + o.min_piece + " of the mesh's)" : std::string()) << "\n"
            << "mesh           " << r.vertices << " vertices, " << r.triangles << " triangles"
            << (r.colored ? ", coloured" : ", no colour") << "\n";
    if (std::any_of(o.outputs.begin(), o.outputs.end(), is_draco)) {
        const int bits = position_bits(mesh, o.draco);
        summary << "draco          " << bits << " bits" << (o.draco.position_bits == 0 ? " (auto)" : "")
                << " position quantization, step " << two_digits(quantization_step(mesh, bits));
        if (mesh.cell_size > 0) summary << " (a tenth of a cell is " << two_digits(mesh.cell_size / 10) << ")";
        summary << ", level " << o.draco.level << "\n";
    }
    for (const auto& [path, bytes] : r.outputs) summary << "output         " << path << " (" << bytes << " bytes)\n";
    summary << std::fixed << std::setprecision(3) << "seconds        read+accumulate " << r.read_accumulate
            << ", extract " << r.extract << ", write " << r.write << " (";
    for (std::size_t i = 0; i < o.outputs.size(); ++i)
        summary << (i ? ", " : "") << extension(o.outputs[i]).substr(1) << " " << r.output_seconds[i];
    summary << "), total " << r.total << "\n"
            << "memory         " << megabytes(r.peak_rss_bytes) << " peak resident\n";
}

} // namespace

void run_mesh(const MeshOptions& o, std::ostream& summary) {
    if (o.outputs.empty()) throw Error(ErrorKind::usage, "no output: give -o OUT.ply, OUT.drc or OUT.glb");
    for (const std::string& path : o.outputs) {
        if (extension(path) != ".ply" && !is_draco(path))
            throw Error(ErrorKind::usage, "-o \"" + path + "\": unknown output extension, expected .ply, .drc or .glb");
        check_output_folder(path); // before reading: nobody should wait to learn this
    }
    if (!o.report.empty()) check_output_folder(o.report);
    AccumulateOptions accumulate = accumulate_options(o.grid);
    const double requested_iso = parse_iso(o.iso);
    const MinPiece min_piece = parse_min_piece(o.min_piece);
    const VertexPlacement placement = parse_placement(o.placement);
    std::optional<tbb::global_control> thread_limit;
    if (o.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, o.threads);
    Progress progress(summary, o.progress && !o.quiet);
    auto verbose = [&](const std::string& line) {
        if (!o.verbose) return;
        progress.clear();
        summary << line << "\n";
    };

    RunReport r;
    const auto start = std::chrono::steady_clock::now();
    if (o.grid.scan_bounds) accumulate.bounds = scan_bounds(o.input);
    LasReader reader(o.input);
    // An empty mesh is no use and Draco cannot encode one: say so before any device work.
    if (reader.header().point_count == 0)
        throw_input_error(reader.stream().name(), "the header promises no point records (point count 0): nothing to mesh");
    ComputeDevice device(o.grid.device);
    r.input = reader.stream().name();
    r.device = device.info().name;
    verbose("reading        " + r.input + ": LAS " + version_string(reader.header()) + ", point format " +
            std::to_string(reader.header().point_format) + ", " + std::to_string(reader.header().point_count) +
            " points promised");
    verbose("device         " + r.device + " (" + device.info().platform + "), " +
            megabytes(device.info().global_memory) + " memory, largest buffer " + megabytes(device.info().max_alloc));
    accumulate.on_slice = [&](std::uint64_t points) {
        progress.reading(points, reader.header().point_count, reader.stream().raw_position(), reader.stream().raw_size());
    };
    const DensityGrid grid = accumulate_density(reader, device, accumulate);
    r.read_accumulate = seconds_since(start);
    r.points_read = grid.points_read, r.points_outside = grid.points_outside, r.grid = grid.spec;
    if (!o.quiet && grid.points_outside > 0) {
        progress.clear();
        summary << outside_advice(grid.points_outside, grid.points_read);
    }
    verbose("accumulated    " + std::to_string(grid.points_read) + " points into " +
            megabytes(memory_need(grid.spec, grid.has_color(), 0).largest_buffer) + " of grid in " +
            two_digits(r.read_accumulate) + " s");

    progress.stage("extracting the surface");
    const auto extract_start = std::chrono::steady_clock::now();
    r.iso_auto = requested_iso < 0;
    r.iso = r.iso_auto ? automatic_iso(grid) : requested_iso;
    r.placement = placement;
    Mesh mesh = extract_isosurface(grid, r.iso, placement);
    verbose("extracted      " + std::to_string(mesh.triangles.size()) + " triangles at iso " + format_double(r.iso));
    r.pieces = remove_small_pieces(mesh, min_piece);
    r.extract = seconds_since(extract_start);
    r.vertices = mesh.positions.size(), r.triangles = mesh.triangles.size(), r.colored = !mesh.colors.empty();
    r.origin = mesh.origin;

    const auto write_start = std::chrono::steady_clock::now();
    for (const std::string& path : o.outputs) {
        progress.stage("writing " + path);
        const auto output_start = std::chrono::steady_clock::now();
        write_output(mesh, path, o);
        r.output_seconds.push_back(seconds_since(output_start));
        r.outputs.emplace_back(path, std::filesystem::file_size(path));
        verbose("wrote          " + path + " in " + two_digits(r.output_seconds.back()) + " s");
    }
    r.write = seconds_since(write_start);
    r.total = seconds_since(start);
    r.peak_rss_bytes = peak_rss_bytes();
    progress.clear();
    if (!o.report.empty()) write_report_json(r, o.report);
    if (!o.quiet) print_summary(r, o, mesh, summary);
}

} // namespace lasmesh::cli
