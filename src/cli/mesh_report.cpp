// SPDX-License-Identifier: Apache-2.0
// The summary and the --report JSON: same fields, same order, one for people, one for programs.
#include "mesh_report.hpp"

#include "grid/cell_sums.hpp"
#include "io/draco_writer.hpp"
#include "io/json.hpp"
#include "io/output_file.hpp"
#include "number_text.hpp"

#include <filesystem>
#include <iomanip>
#include <sstream>

namespace lasmesh::cli {

namespace {

// "ply", "drc", "glb": the extension as given, lower case, for the per-output timings.
std::string extension_name(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext.empty() ? ext : ext.substr(1);
}

// " m", " ft", " ftUS" after a length in the CRS's unit; nothing without a CRS.
std::string unit_suffix(const std::string& unit) {
    if (unit.empty()) return "";
    if (unit == "metre") return " m";
    if (unit == "foot") return " ft";
    if (unit == "US survey foot") return " ftUS";
    return " " + unit;
}

} // namespace

void print_summary(const RunReport& r, const SummaryContext& c, std::ostream& summary) {
    const auto& s = r.grid;
    summary << std::setprecision(6) << "input          " << r.input << "\n";
    for (const std::string& skipped : r.skipped_inputs) summary << "skipped        " << skipped << "\n";
    summary << "device         " << r.device << "\n"
            << "points         " << r.points_read << " read, " << r.points_outside << " outside the grid\n"
            << "crs            " << (r.crs.empty() ? "none declared: the mesh is in the file's own units" : r.crs)
            << "\n"
            << "grid           " << s.dims[0] << " x " << s.dims[1] << " x " << s.dims[2] << " cells of "
            << four_digits(s.cell_size) << unit_suffix(r.unit)
            << (r.grid_reason.empty() ? "" : " (" + r.grid_reason + ")") << "\n"
            << "iso            " << four_digits(r.iso) << (r.iso_auto ? " (auto)" : "") << " points per cell, "
            << (r.surface == SurfaceKind::sheet       ? "one sheet through the points"
                : r.placement == VertexPlacement::iso ? "closed, vertices on the iso level"
                                                      : "closed, vertices on the surface")
            << "\n"
            << "occupied       " << r.occupied_cells << " cells in " << r.occupied_bricks << " bricks of "
            << CellGrid::brick_cells << ", " << megabytes(r.pool_bytes) << " of grid on the device, "
            << megabytes(r.host_grid_bytes) << " on the host\n"
            << "origin         " << coordinate(r.origin[0], r.grid.cell_size / 1000) << " "
            << coordinate(r.origin[1], r.grid.cell_size / 1000) << " "
            << coordinate(r.origin[2], r.grid.cell_size / 1000)
            << " (output positions are relative to it; exact in each file and in --report)\n"
            << (r.thin_cells > 0 ? "thin parts     " + std::to_string(r.thin_cells) + " cells meshed at cells of " +
                                       four_digits(r.grid.cell_size / 2) + unit_suffix(r.unit) + ", read again in " +
                                       two_digits(r.thin_read) + " s\n"
                : !r.thin_unrefined.empty() ? "thin parts     none refined: " + r.thin_unrefined + "\n"
                                            : std::string())
            << "pieces         " << r.pieces.pieces << " connected, " << r.pieces.removed << " removed ("
            << r.pieces.triangles_removed << " triangles) below a diagonal of " << four_digits(r.pieces.min_diagonal)
            << unit_suffix(r.unit)
            << (c.relative_min_piece ? " (" + c.min_piece_text + " of the mesh's)"
                : r.unit.empty()     ? " (in the file's units)"
                                     : "")
            << "\n"
            << "simplify       ";
    if (r.simplify.error > 0)
        summary << r.simplify.triangles_before << " to " << r.simplify.triangles_after << " triangles, bound "
                << four_digits(r.simplify.error) << unit_suffix(r.unit) << " (" << c.simplify_text << "), in "
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
