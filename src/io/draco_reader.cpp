// Draco and GLB decoding. The GLB container is parsed here (12-byte header, JSON chunk, BIN chunk);
// its JSON with Boost.PropertyTree, which is enough for the few fields needed.
#include "lasmesh/io/draco_reader.hpp"

#include "lasmesh/byte_order.hpp"
#include "lasmesh/io/draco_writer.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/io/srgb.hpp"

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>
#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace lasmesh {

namespace {

std::string read_whole_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorKind::input, path + ": cannot open");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (in.bad()) throw Error(ErrorKind::input, path + ": read failed");
    return std::move(bytes).str();
}

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
             const std::string& name) {
    if (!position || position->num_components() != 3)
        throw Error(ErrorKind::input, name + ": no 3-component POSITION attribute");
    if (color && (color->num_components() != 3 || (color->data_type() != draco::DT_UINT8 && color->data_type() != draco::DT_UINT16)))
        throw Error(ErrorKind::input, name + ": the COLOR attribute is not 3 components of 8 or 16 bits");
    Mesh mesh;
    const draco::PointIndex::ValueType points = in.num_points();
    mesh.positions.resize(points);
    if (color) mesh.colors.resize(points);
    for (draco::PointIndex p(0); p < points; ++p) {
        position->ConvertValue<float, 3>(position->mapped_index(p), mesh.positions[p.value()].data());
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
    }
    return mesh;
}

using Json = boost::property_tree::ptree;

// Element `index` of a JSON array.
const Json& element(const Json& array, std::size_t index, const std::string& what) {
    if (index >= array.size()) throw std::out_of_range(what + " has no element " + std::to_string(index));
    return std::next(array.begin(), static_cast<std::ptrdiff_t>(index))->second;
}

std::vector<double> numbers(const Json& array) {
    std::vector<double> values;
    for (const auto& item : array) values.push_back(item.second.get_value<double>());
    return values;
}

// Whether a node rotation (x, y, z, w) is write_glb's: -90 degrees about x.
bool is_z_up_to_y_up(const std::vector<double>& q) {
    const double h = std::sqrt(0.5);
    return q.size() == 4 && std::abs(q[0] + h) < 1e-9 && std::abs(q[1]) < 1e-9 && std::abs(q[2]) < 1e-9 &&
           std::abs(q[3] - h) < 1e-9;
}

} // namespace

Mesh decode_draco(std::string_view bytes, const std::string& name) {
    const auto decoded = decode_stream(bytes, name);
    return to_mesh(*decoded, decoded->GetNamedAttribute(draco::GeometryAttribute::POSITION),
                   decoded->GetNamedAttribute(draco::GeometryAttribute::COLOR), name);
}

Mesh read_draco(const std::string& path) { return decode_draco(read_whole_file(path), path); }

Mesh read_glb(const std::string& path) {
    const std::string file = read_whole_file(path);
    const auto* bytes = reinterpret_cast<const std::byte*>(file.data());
    auto u32 = [&](std::size_t at) { return load_le<std::uint32_t>(bytes + at); };
    if (file.size() < 20 || file.compare(0, 4, "glTF") != 0 || u32(4) != 2)
        throw Error(ErrorKind::input, path + ": not a glTF 2.0 binary file (GLB)");
    if (u32(8) != file.size()) throw Error(ErrorKind::input, path + ": the GLB header gives " + std::to_string(u32(8)) +
                                                                 " bytes, the file has " + std::to_string(file.size()));
    const std::size_t json_length = u32(12);
    if (u32(16) != 0x4E4F534A || 20 + json_length > file.size())
        throw Error(ErrorKind::input, path + ": the first GLB chunk is not a complete JSON chunk");
    const std::size_t bin_at = 20 + json_length;
    if (bin_at + 8 > file.size() || u32(bin_at + 4) != 0x004E4942 || bin_at + 8 + u32(bin_at) > file.size())
        throw Error(ErrorKind::input, path + ": no complete BIN chunk after the JSON chunk");
    const std::string_view bin = std::string_view(file).substr(bin_at + 8, u32(bin_at));

    try {
        Json gltf;
        std::istringstream json(file.substr(20, json_length));
        boost::property_tree::read_json(json, gltf);
        const Json& primitive = element(element(gltf.get_child("meshes"), 0, "meshes").get_child("primitives"), 0, "primitives");
        const Json& draco = primitive.get_child("extensions.KHR_draco_mesh_compression");
        const Json& view = element(gltf.get_child("bufferViews"), draco.get<std::size_t>("bufferView"), "bufferViews");
        if (view.get<int>("buffer") != 0) throw std::out_of_range("the Draco buffer view is not in the GLB's BIN chunk");
        const std::size_t offset = view.get<std::size_t>("byteOffset", 0), length = view.get<std::size_t>("byteLength");
        if (offset > bin.size() || length > bin.size() - offset)
            throw std::out_of_range("the Draco buffer view runs past the BIN chunk");

        const auto decoded = decode_stream(bin.substr(offset, length), path);
        const auto color_id = draco.get_optional<int>("attributes.COLOR_0");
        Mesh mesh = to_mesh(*decoded, decoded->GetAttributeByUniqueId(draco.get<int>("attributes.POSITION")),
                            color_id ? decoded->GetAttributeByUniqueId(*color_id) : nullptr, path);

        // The node's translation is the origin in glTF's Y-up axes (see write_glb): turn it back.
        const Json& node = element(gltf.get_child("nodes"), 0, "nodes");
        const auto translation = node.get_child_optional("translation");
        const auto rotation = node.get_child_optional("rotation");
        const std::vector<double> t = translation ? numbers(*translation) : std::vector<double>{0, 0, 0};
        if (t.size() != 3) throw std::out_of_range("the node's translation is not 3 numbers");
        if (!rotation) {
            mesh.origin = {t[0], t[1], t[2]};
        } else if (is_z_up_to_y_up(numbers(*rotation))) {
            mesh.origin = {t[0], -t[2], t[1]};
        } else {
            throw std::out_of_range("the node's rotation is not lasmesh's Z-up to Y-up rotation");
        }
        return mesh;
    } catch (const boost::property_tree::ptree_error& e) {
        throw Error(ErrorKind::input, path + ": glTF JSON: " + e.what());
    } catch (const std::out_of_range& e) {
        throw Error(ErrorKind::input, path + ": " + e.what());
    }
}

} // namespace lasmesh
