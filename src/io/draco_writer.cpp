// SPDX-License-Identifier: Apache-2.0
// Draco encoding: the Mesh copied into a draco::Mesh (one point per vertex, so connectivity is
// kept as it is), then compressed by draco::Encoder.
#include "io/draco_writer.hpp"

#include "io/output_file.hpp"
#include "io/srgb.hpp"
#include "lasmesh/error.hpp"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>

#include <algorithm>
#include <memory>

namespace lasmesh {

double position_range(const Mesh& mesh) {
    if (mesh.positions.empty()) return 0;
    std::array<float, 3> lo = mesh.positions[0], hi = mesh.positions[0];
    for (const auto& p : mesh.positions)
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], p[c]);
            hi[c] = std::max(hi[c], p[c]);
        }
    double range = 0;
    for (int c = 0; c < 3; ++c) range = std::max(range, double(hi[c]) - double(lo[c]));
    return range;
}

double quantization_step(const Mesh& mesh, int bits) {
    return position_range(mesh) / static_cast<double>((std::uint64_t{1} << bits) - 1);
}

int automatic_position_bits(const Mesh& mesh) {
    if (!(mesh.cell_size > 0)) return 14;
    // Below 8 bits the step would be coarse next to the mesh's own size; a tiny mesh costs little.
    for (int bits = 8; bits < 16; ++bits)
        if (quantization_step(mesh, bits) <= mesh.cell_size / 10) return bits;
    return 16;
}

int position_bits(const Mesh& mesh, const DracoOptions& options) {
    if (options.position_bits < 0 || options.position_bits > 30)
        throw Error(ErrorKind::usage,
                    "Draco position bits must be 1 to 30, not " + std::to_string(options.position_bits));
    if (options.level < 0 || options.level > 10)
        throw Error(ErrorKind::usage, "Draco level must be 0 to 10, not " + std::to_string(options.level));
    return options.position_bits > 0 ? options.position_bits : automatic_position_bits(mesh);
}

namespace {

// Adds an attribute with one value per point, filled from `value(i)`, with the given unique id.
template <typename T, typename Value>
void add_attribute(draco::Mesh& out, draco::GeometryAttribute::Type type, draco::DataType data_type, bool normalized,
                   int unique_id, Value value) {
    draco::GeometryAttribute attribute;
    attribute.Init(type, nullptr, 3, data_type, normalized, 3 * sizeof(T), 0);
    const int id = out.AddAttribute(attribute, true, out.num_points());
    draco::PointAttribute* added = out.attribute(id);
    added->set_unique_id(unique_id);
    for (draco::PointIndex::ValueType i = 0; i < out.num_points(); ++i) {
        const std::array<T, 3> v = value(i);
        added->SetAttributeValue(draco::AttributeValueIndex(i), v.data());
    }
}

} // namespace

std::string encode_draco(const Mesh& mesh, const DracoOptions& options, DracoColor color) {
    const int bits = position_bits(mesh, options);
    draco::Mesh out;
    out.set_num_points(static_cast<draco::PointIndex::ValueType>(mesh.positions.size()));
    add_attribute<float>(out, draco::GeometryAttribute::POSITION, draco::DT_FLOAT32, false, draco_position_id,
                         [&](std::size_t i) { return mesh.positions[i]; });
    if (!mesh.normals.empty())
        add_attribute<float>(out, draco::GeometryAttribute::NORMAL, draco::DT_FLOAT32, false, draco_normal_id,
                             [&](std::size_t i) { return mesh.normals[i]; });
    if (!mesh.colors.empty() && color == DracoColor::srgb8)
        add_attribute<std::uint8_t>(out, draco::GeometryAttribute::COLOR, draco::DT_UINT8, true, draco_color_id,
                                    [&](std::size_t i) { return mesh.colors[i]; });
    if (!mesh.colors.empty() && color == DracoColor::linear16)
        add_attribute<std::uint16_t>(out, draco::GeometryAttribute::COLOR, draco::DT_UINT16, true, draco_color_id,
                                     [&](std::size_t i) {
                                         const auto& c = mesh.colors[i];
                                         return std::array<std::uint16_t, 3>{
                                             srgb8_to_linear16(c[0]), srgb8_to_linear16(c[1]), srgb8_to_linear16(c[2])};
                                     });
    out.SetNumFaces(mesh.triangles.size());
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        const auto& t = mesh.triangles[f];
        out.SetFace(draco::FaceIndex(static_cast<draco::FaceIndex::ValueType>(f)),
                    {draco::PointIndex(t[0]), draco::PointIndex(t[1]), draco::PointIndex(t[2])});
    }

    auto metadata = std::make_unique<draco::GeometryMetadata>();
    metadata->AddEntryDoubleArray(draco_origin_entry, {mesh.origin[0], mesh.origin[1], mesh.origin[2]});
    for (int a = 0; a < 3; ++a) metadata->AddEntryDouble(draco_origin_axis_entries[a], mesh.origin[a]);
    if (mesh.cell_size > 0) metadata->AddEntryDouble(draco_cell_size_entry, mesh.cell_size);
    if (!mesh.crs.empty()) metadata->AddEntryString(draco_crs_entry, mesh.crs);
    out.AddMetadata(std::move(metadata));

    draco::Encoder encoder;
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, bits);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, options.normal_bits);
    encoder.SetSpeedOptions(10 - options.level, 10 - options.level);
    draco::EncoderBuffer buffer;
    const draco::Status status = encoder.EncodeMeshToBuffer(out, &buffer);
    if (!status.ok())
        throw Error(ErrorKind::output, std::string("Draco cannot encode the mesh: ") + status.error_msg());
    return std::string(buffer.data(), buffer.size());
}

void write_draco(const Mesh& mesh, const std::string& path, const DracoOptions& options) {
    write_encoded(path, "Draco", mesh.triangles.empty(), [&] { return encode_draco(mesh, options); });
}

} // namespace lasmesh
