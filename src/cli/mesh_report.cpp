// The summary and the --report JSON: same fields, same order, one for people, one for programs.
#include "mesh_report.hpp"

#include "json.hpp"
#include "lasmesh/number_text.hpp"
#include "lasmesh/io/output_file.hpp"

#include <filesystem>
#include <iomanip>
#include <sstream>

namespace lasmesh::cli {

namespace {

const char* placement_name(VertexPlacement placement) {
    return placement == VertexPlacement::iso ? "iso" : "surface";
}

// "ply", "drc", "glb": the extension as given, lower case, for the per-output timings.
std::string extension_name(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext.empty() ? ext : ext.substr(1);
}

} // namespace

void write_report_json(const RunReport& r, const std::string& path) {
    Json json;
    json["input"] = r.input;
    json["device"] = r.device;
    json["points_read"] = r.points_read;
    json["points_outside"] = r.points_outside;
    json["grid"] = {{"dims", r.grid.dims}, {"cell_size", r.grid.cell_size}, {"origin", r.grid.origin}};
    if (!r.grid_reason.empty()) json["grid"]["reason"] = r.grid_reason;
    json["iso"] = r.iso;
    json["iso_auto"] = r.iso_auto;
    json["surface"] = r.surface == SurfaceKind::sheet ? "sheet" : "closed";
    json["placement"] = placement_name(r.placement);
    json["sparse_grid"] = {{"occupied_cells", r.occupied_cells}, {"occupied_bricks", r.occupied_bricks},
                           {"brick_cells", DensityGrid::brick_cells}, {"pool_bytes", r.pool_bytes}, {"host_grid_bytes", r.host_grid_bytes}};
    json["pieces"] = {{"connected", r.pieces.pieces}, {"removed", r.pieces.removed}, {"min_diagonal", r.pieces.min_diagonal}};
    json["simplify"] = {{"triangles_before", r.simplify.triangles_before}, {"triangles_after", r.simplify.triangles_after},
                        {"error", r.simplify.error}, {"seconds", r.simplify.seconds}};
    json["vertices"] = r.vertices;
    json["triangles"] = r.triangles;
    json["colored"] = r.colored;
    json["normals"] = r.normals;
    json["origin"] = r.origin;
    json["outputs"] = Json::array();
    for (const OutputReport& output : r.outputs)
        json["outputs"].push_back({{"path", output.path}, {"bytes", output.bytes}, {"seconds", output.seconds}});
    json["seconds"] = {{"read_accumulate", r.read_accumulate}, {"extract", r.extract}, {"write", r.write}, {"total", r.total}};
    json["peak_rss_bytes"] = r.peak_rss_bytes;
    OutputFile out(path);
    out.write(json_line(json) + "\n");
    out.commit();
}

void print_summary(const RunReport& r, const SummaryContext& c, std::ostream& summary) {
    const auto& s = r.grid;
    summary << std::setprecision(6) << "input          " << r.input << "\n"
            << "device         " << r.device << "\n"
            << "points         " << r.points_read << " read, " << r.points_outside << " outside the grid\n"
            << "grid           " << s.dims[0] << " x " << s.dims[1] << " x " << s.dims[2] << " cells of "
            << format_double(s.cell_size) << (r.grid_reason.empty() ? "" : " (" + r.grid_reason + ")") << "\n"
            << "iso            " << format_double(r.iso) << (r.iso_auto ? " (auto)" : "")
            << " points per cell, "
            << (r.surface == SurfaceKind::sheet ? "one sheet through the points"
                : r.placement == VertexPlacement::iso ? "closed, vertices on the iso level"
                                                      : "closed, vertices on the surface")
            << "\n"
            << "occupied       " << r.occupied_cells << " cells in " << r.occupied_bricks << " bricks of "
            << DensityGrid::brick_cells << ", " << format_double(r.pool_bytes / 1e6) << " MB of grid on the device, "
            << format_double(r.host_grid_bytes / 1e6) << " MB on the host\n"
            << "origin         " << format_double(r.origin[0]) << " " << format_double(r.origin[1]) << " "
            << format_double(r.origin[2]) << " (output positions are relative to it)\n"
            << "pieces         " << r.pieces.pieces << " connected, " << r.pieces.removed << " removed ("
            << r.pieces.triangles_removed << " triangles) below a diagonal of " << format_double(r.pieces.min_diagonal)
            << (c.relative_min_piece ? " (" + c.min_piece_text + " of the mesh's)" : std::string()) << "\n"
            << "simplify       ";
    if (r.simplify.error > 0)
        summary << r.simplify.triangles_before << " to " << r.simplify.triangles_after << " triangles, bound "
                << format_double(r.simplify.error) << " (" << c.simplify_text << "), in "
                << two_digits(r.simplify.seconds) << " s\n";
    else
        summary << "off\n";
    summary << "mesh           " << r.vertices << " vertices, " << r.triangles << " triangles"
            << (r.colored ? ", coloured" : ", no colour") << (r.normals ? ", normals" : "") << "\n";
    if (c.any_draco && c.mesh) {
        const int bits = position_bits(*c.mesh, c.draco);
        summary << "draco          " << bits << " bits" << (c.draco.position_bits == 0 ? " (auto)" : "")
                << " position quantization, step " << two_digits(quantization_step(*c.mesh, bits));
        if (c.mesh->cell_size > 0) summary << " (a tenth of a cell is " << two_digits(c.mesh->cell_size / 10) << ")";
        summary << ", level " << c.draco.level << "\n";
    }
    for (const OutputReport& output : r.outputs)
        summary << "output         " << output.path << " (" << output.bytes << " bytes)\n";
    summary << std::fixed << std::setprecision(3) << "seconds        read+accumulate " << r.read_accumulate
            << ", extract " << r.extract << ", write " << r.write << " (";
    for (std::size_t i = 0; i < r.outputs.size(); ++i)
        summary << (i ? ", " : "") << extension_name(r.outputs[i].path) << " " << r.outputs[i].seconds;
    summary << "), total " << r.total << "\n"
            << "memory         " << megabytes(r.peak_rss_bytes) << " peak resident\n";
}

} // namespace lasmesh::cli
