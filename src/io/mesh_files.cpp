// SPDX-License-Identifier: Apache-2.0
// One entry for every mesh format: the format from the extension, then the format's writer or
// reader (ply_*, draco_*, gltf_*).
#include "lasmesh/mesh_files.hpp"

#include "io/draco_reader.hpp"
#include "io/draco_writer.hpp"
#include "io/gltf_reader.hpp"
#include "io/gltf_writer.hpp"
#include "io/html_writer.hpp"
#include "io/output_file.hpp"
#include "io/ply_reader.hpp"
#include "io/ply_writer.hpp"
#include "io/png_preview.hpp"
#include "io/write_into.hpp"
#include "lasmesh/error.hpp"

#include <cctype>
#include <filesystem>

namespace lasmesh {

std::optional<MeshFormat> format_from_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".ply") return MeshFormat::ply;
    if (ext == ".drc") return MeshFormat::draco;
    if (ext == ".glb") return MeshFormat::glb;
    if (ext == ".png") return MeshFormat::png;
    if (ext == ".html") return MeshFormat::html;
    if (ext == ".json") return MeshFormat::tileset;
    return std::nullopt;
}

MeshFormat output_format(const OutputRequest& output) {
    const std::optional<MeshFormat> format = output.format ? output.format : format_from_extension(output.path);
    if (!format)
        throw Error(ErrorKind::usage,
                    "output \"" + output.path +
                        "\": unknown extension, expected .ply, .drc, .glb, .png, .html or .json (a tileset)",
                    "outputs");
    return *format;
}

void write_mesh_into(const Mesh& mesh, const OutputRequest& output, MeshFormat format, const std::string& name,
                     OutputFile& file, const std::string& facts_json) {
    if (format == MeshFormat::ply) return write_ply(mesh, file, output.ascii);
    std::string bytes;
    try {
        if (format == MeshFormat::draco)
            bytes = encode_draco(mesh, output.draco);
        else if (format == MeshFormat::glb)
            bytes = encode_glb(mesh, {output.glb_compression, output.glb_origin, name, output.draco});
        else if (format == MeshFormat::html) {
            HtmlOptions page;
            page.name = name;
            page.facts_json = facts_json;
            bytes = encode_html(mesh, page);
        } else
            bytes = encode_png(render_preview(mesh));
    } catch (const Error& e) {
        throw Error(e.kind(), output.path + ": " + e.what());
    }
    file.write(bytes);
}

void write_mesh(const Mesh& mesh, const OutputRequest& output, const std::string& name) {
    const MeshFormat format = output_format(output);
    if (format == MeshFormat::tileset)
        throw Error(ErrorKind::usage,
                    "output \"" + output.path + "\": a tileset is written by build_mesh, from the grid", "outputs");
    if (format != MeshFormat::ply && mesh.triangles.empty())
        throw Error(ErrorKind::output, output.path + ": the mesh has no triangles");
    OutputFile file(output.path);
    write_mesh_into(mesh, output, format, name, file);
    file.commit();
}

Mesh read_mesh(const std::string& path) {
    const std::optional<MeshFormat> format = format_from_extension(path);
    if (format == MeshFormat::ply) return read_ply(path);
    if (format == MeshFormat::draco) return read_draco(path);
    if (format == MeshFormat::glb) return read_glb(path);
    throw Error(ErrorKind::usage, "\"" + path + "\": unknown mesh extension, expected .ply, .drc or .glb");
}

} // namespace lasmesh
