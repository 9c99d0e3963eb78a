// SPDX-License-Identifier: Apache-2.0
// The run report as JSON: the fields of RunReport in the order of the text summary, full precision.
#include "lasmesh/build_mesh.hpp"

#include "grid/cell_sums.hpp"
#include "io/json.hpp"

namespace lasmesh {

std::string run_report_json(const RunReport& r) {
    Json json;
    json["input"] = r.input;
    json["input_files"] = r.input_files;
    json["skipped_inputs"] = r.skipped_inputs;
    json["device"] = r.device;
    json["points_read"] = r.points_read;
    json["points_outside"] = r.points_outside;
    json["grid"] = {{"dims", r.grid.dims}, {"cell_size", r.grid.cell_size}, {"origin", r.grid.origin}};
    if (!r.grid_reason.empty()) json["grid"]["reason"] = r.grid_reason;
    json["iso"] = r.iso;
    json["iso_auto"] = r.iso_auto;
    json["surface"] = r.surface == SurfaceKind::sheet ? "sheet" : "closed";
    if (r.surface == SurfaceKind::closed) json["placement"] = r.placement == VertexPlacement::iso ? "iso" : "surface";
    json["sparse_grid"] = {{"occupied_cells", r.occupied_cells}, {"occupied_bricks", r.occupied_bricks},
                           {"median_count", r.median_count},     {"brick_cells", CellGrid::brick_cells},
                           {"pool_bytes", r.pool_bytes},         {"host_grid_bytes", r.host_grid_bytes}};
    if (r.thin_cells > 0)
        json["thin_parts"] = {
            {"cells", r.thin_cells}, {"cell_size", r.grid.cell_size / 2}, {"read_seconds", r.thin_read}};
    else if (!r.thin_unrefined.empty())
        json["thin_parts"] = {{"cells", 0}, {"unrefined", r.thin_unrefined}};
    json["pieces"] = {
        {"connected", r.pieces.pieces}, {"removed", r.pieces.removed}, {"min_diagonal", r.pieces.min_diagonal}};
    json["simplify"] = {{"triangles_before", r.simplify.triangles_before},
                        {"triangles_after", r.simplify.triangles_after},
                        {"error", r.simplify.error},
                        {"seconds", r.simplify.seconds}};
    json["vertices"] = r.vertices;
    json["triangles"] = r.triangles;
    json["colored"] = r.colored;
    json["normals"] = r.normals;
    json["origin"] = r.origin;
    json["crs"] = {{"summary", r.crs}, {"recorded", r.crs_recorded}, {"unit", r.unit}};
    json["outputs"] = Json::array();
    for (const OutputReport& output : r.outputs)
        json["outputs"].push_back({{"path", output.path}, {"bytes", output.bytes}, {"seconds", output.seconds}});
    json["seconds"] = {
        {"read_accumulate", r.read_accumulate}, {"extract", r.extract}, {"write", r.write}, {"total", r.total}};
    json["peak_rss_bytes"] = r.peak_rss_bytes;
    return json_line(json) + "\n";
}

} // namespace lasmesh
