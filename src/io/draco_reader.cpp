// SPDX-License-Identifier: Apache-2.0
// Draco decoding through Draco's decoder: a .drc file, or the stream of a .glb's Draco
// primitive (gltf_reader.cpp).
#include "io/draco_reader.hpp"

#include "io/draco_writer.hpp"
#include "io/mesh_file.hpp"
#include "io/srgb.hpp"
#include "lasmesh/error.hpp"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include <fstream>
#include <sstream>

namespace lasmesh {

namespace {

std::unique_ptr<draco::Mesh> decode_stream(std::string_view bytes, const std::string& name) {
    draco::DecoderBuffer buffer;
    buffer.Init(bytes.data(), bytes.size());
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) throw Error(ErrorKind::input, name + ": not a Draco mesh: " + decoded.status().error_msg());
    return std::move(decoded).value();
}

// The Mesh of a decoded Draco mesh, with its positions and colours from the given attributes.
Mesh to_mesh(const draco::Mesh& in, const draco::PointAttribute* position, const draco::PointAttribute* color,
             const draco::PointAttribute* normal, const std::string& name) {
    if (!position || position->num_components() != 3)
        throw Error(ErrorKind::input, name + ": no 3-component POSITION attribute");
    if (color && (color->num_components() != 3 ||
                  (color->data_type() != draco::DT_UINT8 && color->data_type() != draco::DT_UINT16)))
        throw Error(ErrorKind::input, name + ": the COLOR attribute is not 3 components of 8 or 16 bits");
    Mesh mesh;
    const draco::PointIndex::ValueType points = in.num_points();
    mesh.positions.resize(points);
    if (color) mesh.colors.resize(points);
    if (normal && normal->num_components() == 3) mesh.normals.resize(points);
    for (draco::PointIndex p(0); p < points; ++p) {
        position->ConvertValue<float, 3>(position->mapped_index(p), mesh.positions[p.value()].data());
        if (!mesh.normals.empty())
            normal->ConvertValue<float, 3>(normal->mapped_index(p), mesh.normals[p.value()].data());
        if (color && color->data_type() == draco::DT_UINT8) {
            color->GetValue(color->mapped_index(p), mesh.colors[p.value()].data());
        } else if (color) {
            std::array<std::uint16_t, 3> linear;
            color->GetValue(color->mapped_index(p), linear.data());
            for (int c = 0; c < 3; ++c) mesh.colors[p.value()][c] = linear16_to_srgb8(linear[c]);
        }
    }
    mesh.triangles.resize(in.num_faces());
    for (draco::FaceIndex f(0); f < in.num_faces(); ++f)
        for (int c = 0; c < 3; ++c) mesh.triangles[f.value()][c] = in.face(f)[c].value();

    if (const draco::GeometryMetadata* metadata = in.GetMetadata()) {
        std::vector<double> origin;
        if (metadata->GetEntryDoubleArray(draco_origin_entry, &origin) && origin.size() == 3)
            mesh.origin = {origin[0], origin[1], origin[2]};
        metadata->GetEntryDouble(draco_cell_size_entry, &mesh.cell_size);
        metadata->GetEntryString(draco_crs_entry, &mesh.crs);
    }
    return mesh;
}

} // namespace

std::string read_whole_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorKind::input, path + ": cannot open");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (in.bad()) throw Error(ErrorKind::input, path + ": read failed");
    return std::move(bytes).str();
}

Mesh decode_draco_attributes(std::string_view bytes, const std::string& name, int position_id,
                             std::optional<int> color_id, std::optional<int> normal_id) {
    const auto decoded = decode_stream(bytes, name);
    return to_mesh(*decoded, decoded->GetAttributeByUniqueId(position_id),
                   color_id ? decoded->GetAttributeByUniqueId(*color_id) : nullptr,
                   normal_id ? decoded->GetAttributeByUniqueId(*normal_id) : nullptr, name);
}

Mesh decode_draco(std::string_view bytes, const std::string& name) {
    const auto decoded = decode_stream(bytes, name);
    return to_mesh(*decoded, decoded->GetNamedAttribute(draco::GeometryAttribute::POSITION),
                   decoded->GetNamedAttribute(draco::GeometryAttribute::COLOR),
                   decoded->GetNamedAttribute(draco::GeometryAttribute::NORMAL), name);
}

Mesh read_draco(const std::string& path) {
    return decode_draco(read_whole_file(path), path);
}

} // namespace lasmesh
