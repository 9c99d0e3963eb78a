// SPDX-License-Identifier: Apache-2.0
// `lasmesh compare`: reads the mesh, streams the cloud, prints the distance statistics.
#include "compare_command.hpp"
#include "option_parsing.hpp"
#include "progress.hpp"

#include "io/html_writer.hpp"
#include "io/json.hpp"
#include "io/output_file.hpp"
#include "io/ply_reader.hpp"
#include "io/ply_writer.hpp"
#include "io/same_file.hpp"
#include "lasmesh/compare.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/mesh_files.hpp"
#include "number_text.hpp"
#include "read/crs.hpp"
#include "read/crs_transform.hpp"
#include "read/input_stream.hpp"

#include <filesystem>
#include <iomanip>

namespace lasmesh::cli {

namespace {

Json stats_json(const DistanceStats& s) {
    Json json = {{"mean", s.mean}, {"std", s.std}, {"median", s.median},
                 {"p95", s.p95},   {"p99", s.p99}, {"max", s.max}};
    if (s.within_1_cell >= 0) {
        json["within_1_cell"] = s.within_1_cell;
        json["within_2_cells"] = s.within_2_cells;
        json["mean_within_2_cells"] = s.mean_within_2_cells;
    }
    return json;
}

void print_stats(std::ostream& out, const char* name, const DistanceStats& s) {
    out << name << "mean " << s.mean << ", std " << s.std << ", median " << s.median << ", p95 " << s.p95 << ", p99 "
        << s.p99 << ", max " << s.max;
    if (s.within_1_cell >= 0)
        out << "; within 1 cell " << 100 * s.within_1_cell << "%, 2 cells " << 100 * s.within_2_cells
            << "% (mean of those " << s.mean_within_2_cells << ")";
    out << "\n";
}

// The answer first, in a sentence: how close the points are to the mesh, and the mesh to them.
std::string verdict(const CompareResult& r) {
    const DistanceStats& c = r.cloud_to_mesh;
    std::string text = "half of the points lie within " + four_digits(c.median) + " of the mesh";
    if (r.cell_size > 0) {
        text += " (" + two_digits(c.median / r.cell_size) + " cell); " + four_digits(100 * c.within_1_cell) +
                "% within a cell, " + four_digits(100 * c.within_2_cells) + "% within 2 cells";
    }
    return text + "; 95% of the mesh lies within " + four_digits(r.mesh_to_cloud.p95) + " of a point";
}

} // namespace

CLI::App* add_compare_command(CLI::App& app, CompareCommandOptions& o) {
    CLI::App* c = app.add_subcommand("compare", "Distances between a mesh and the point cloud it came from, both ways");
    c->add_option("MESH", o.mesh, "Mesh: .ply (lasmesh's or any triangle PLY), or lasmesh's .drc or .glb")->required();
    c->add_option("INPUT", o.input, "LAS or LAZ file, or - for standard input (gzip, bzip2, xz, zstd recognised)")
        ->required();
    c->add_option("--samples", o.samples, "Cloud points used at most, spread evenly over the file")
        ->type_name("N")
        ->capture_default_str()
        ->check(whole_number(1, std::uint64_t{1} << 34));
    c->add_option("--mesh-samples", o.mesh_samples, "Points sampled on the mesh for the mesh-to-cloud distances")
        ->type_name("N")
        ->capture_default_str()
        ->check(whole_number(1, 100'000'000)); // 3.2 GB of samples and distances
    c->add_option("--cell-size", o.cell_size, "Grid cell edge in file units (default: from the mesh file)")
        ->type_name("LENGTH")
        ->check(positive_number());
    c->add_option("--heatmap", o.heatmap,
                  "Also write the mesh coloured by each vertex's distance to the cloud: FILE.ply, or FILE.html (a "
                  "page for a web browser that shows the mesh's colours or the distances, and measures)")
        ->type_name("FILE.ply|FILE.html");
    c->add_option("--heatmap-scale", o.heatmap_scale,
                  "Distance shown red in the heat map (default: 2 cells, or the p99)")
        ->type_name("LENGTH")
        ->check(positive_number());
    c->add_flag("--json", o.json, "One JSON object instead of text");
    c->footer(
        "Examples:\n  lasmesh compare deck.ply deck.las\n  lasmesh compare deck.drc deck.las --json --samples 1000000\n"
        "  lasmesh compare deck.ply deck.las --heatmap deck-distance.ply\n"
        "  lasmesh compare deck.ply deck.las --heatmap deck-distance.html");
    return c;
}

namespace {

// "metre (the mesh's CRS: WGS 84 / UTM zone 15N, EPSG:32615)".
std::string units_of_mesh(const std::string& recorded) {
    const CrsInfo crs = crs_from_text(recorded);
    return crs.unit + " (the mesh's CRS: " + crs.name + (crs.code.empty() ? "" : ", " + crs.code) + ")";
}

} // namespace

void run_compare(const CompareCommandOptions& o, std::ostream& out, std::ostream& log) {
    if (!o.heatmap.empty()) {
        check_output_folder(o.heatmap);
        check_distinct_files({{"the mesh", o.mesh}, {"the input", o.input}, {"--heatmap", o.heatmap}});
    }
    Progress progress(log, stderr_is_terminal()); // a line redrawn in place, on a terminal only
    progress.stage("reading " + o.mesh);
    Mesh mesh = read_mesh(o.mesh);
    LasReader cloud(o.input);
    CompareOptions options;
    options.samples = o.samples;
    options.mesh_samples = o.mesh_samples;
    options.cell_size = o.cell_size;
    options.on_step = [&](const std::string& step) { progress.stage(step); };
    // Lengths are in the cloud's unit; a mesh that records another CRS is measured against
    // coordinates it was not made in, which the numbers alone would not show.
    const std::optional<CrsInfo> crs = read_crs(cloud.header());
    const std::string cloud_crs = crs && crs->identified() ? crs_for_outputs(*crs) : "";
    const CompareResult r = compare(mesh, cloud, options);
    progress.clear();
    if (!r.cloud_transformed.empty())
        log << "lasmesh: note: the cloud was brought from " << r.cloud_transformed << " (the mesh's CRS)\n";
    else if (!mesh.crs.empty() && mesh.crs != cloud_crs)
        log << "lasmesh: warning: the mesh records the CRS "
            << (mesh.crs.size() > 60 ? mesh.crs.substr(0, 60) + "..." : mesh.crs) << " but the cloud "
            << (cloud_crs.empty() ? std::string("declares none") : "is in " + cloud_crs)
            << ": the distances mean something only if both are in the same coordinates\n";

    if (o.json) {
        Json json;
        json["cloud_to_mesh"] = stats_json(r.cloud_to_mesh);
        json["mesh_to_cloud"] = stats_json(r.mesh_to_cloud);
        json["points_read"] = r.points_read;
        json["points_used"] = r.points_used;
        json["samples_used"] = r.samples_used;
        json["cell_size"] = r.cell_size > 0 ? Json(r.cell_size) : Json(nullptr); // null: unknown
        out << json_line(json) << "\n";
    } else {
        out << "verdict        " << verdict(r) << "\n"
            << "units          "
            << (!r.cloud_transformed.empty() ? units_of_mesh(mesh.crs)
                : crs && crs->identified() && !crs->unit.empty()
                    ? crs->unit + " (the cloud's CRS: " + crs->name + (crs->code.empty() ? "" : ", " + crs->code) + ")"
                    : std::string("the file's (it declares no CRS lasmesh can read; metres in most projected ones)"))
            << "; every length below too\n";
        out << std::setprecision(4) << "mesh           " << o.mesh << ": " << mesh.positions.size() << " vertices, "
            << mesh.triangles.size() << " triangles\n"
            << "cloud          " << cloud.stream().name() << ": " << r.points_read << " points, " << r.points_used
            << " used\n"
            << "cell size      " << (r.cell_size > 0 ? four_digits(r.cell_size) : "unknown (give --cell-size)") << "\n";
        print_stats(out, "cloud to mesh  ", r.cloud_to_mesh);
        out << "               (" << r.points_used << " points)\n";
        print_stats(out, "mesh to cloud  ", r.mesh_to_cloud);
        out << "               (" << r.samples_used << " samples on the surface)\n";
    }

    if (!o.heatmap.empty()) {
        std::vector<double> sorted = r.vertex_distance;
        const double scale = o.heatmap_scale > 0 ? o.heatmap_scale
                             : r.cell_size > 0   ? 2 * r.cell_size
                                                 : summarize(sorted, 0).p99;
        std::vector<std::array<std::uint8_t, 3>> heat(mesh.positions.size());
        for (std::size_t v = 0; v < mesh.positions.size(); ++v) heat[v] = heat_color(r.vertex_distance[v], scale);
        if (format_from_extension(o.heatmap) == MeshFormat::html) { // the mesh's own colours stay, the heat beside
            HtmlOptions page;
            page.name = std::filesystem::path(o.mesh).stem().string();
            const std::string unit = !r.cloud_transformed.empty() ? crs_from_text(mesh.crs).unit
                                     : crs && crs->identified()   ? crs->unit
                                                                  : std::string();
            std::string summary; // "WGS 84 / UTM zone 31N (EPSG:32631)"
            if (!mesh.crs.empty()) {
                const CrsInfo info = crs_from_text(mesh.crs);
                summary = info.name + (info.code.empty() ? "" : " (" + info.code + ")");
            }
            page.facts_json = json_line({{"crs", {{"summary", summary}, {"unit", unit}}}});
            page.heat_colors = heat;
            page.heat_distance = r.vertex_distance;
            page.heat_scale = scale;
            OutputFile file(o.heatmap);
            file.write(encode_html(mesh, page));
            file.commit();
        } else {
            mesh.colors = heat;
            write_ply(mesh, o.heatmap, false);
        }
        log << "heat map       " << o.heatmap << ": blue 0, cyan " << four_digits(scale / 4) << ", green "
            << four_digits(scale / 2) << ", yellow " << four_digits(3 * scale / 4) << ", red " << four_digits(scale)
            << " and beyond (distance from each vertex to the nearest point)\n";
    }
}

} // namespace lasmesh::cli
