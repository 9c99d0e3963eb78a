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

#include <algorithm>
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
             const draco::PointAttribute* normal, const std::string& name) {
    if (!position || position->num_components() != 3)
        throw Error(ErrorKind::input, name + ": no 3-component POSITION attribute");
    if (color && (color->num_components() != 3 || (color->data_type() != draco::DT_UINT8 && color->data_type() != draco::DT_UINT16)))
        throw Error(ErrorKind::input, name + ": the COLOR attribute is not 3 components of 8 or 16 bits");
    Mesh mesh;
    const draco::PointIndex::ValueType points = in.num_points();
    mesh.positions.resize(points);
    if (color) mesh.colors.resize(points);
    if (normal && normal->num_components() == 3) mesh.normals.resize(points);
    for (draco::PointIndex p(0); p < points; ++p) {
        position->ConvertValue<float, 3>(position->mapped_index(p), mesh.positions[p.value()].data());
        if (!mesh.normals.empty()) normal->ConvertValue<float, 3>(normal->mapped_index(p), mesh.normals[p.value()].data());
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


// The primitive's Draco stream, its attributes found by the unique ids the extension names.
Mesh draco_primitive(const Json& gltf, const Json& draco, std::string_view bin, const std::string& path) {
    const Json& view = element(gltf.get_child("bufferViews"), draco.get<std::size_t>("bufferView"), "bufferViews");
    if (view.get<int>("buffer") != 0) throw std::out_of_range("the Draco buffer view is not in the GLB's BIN chunk");
    const std::size_t offset = view.get<std::size_t>("byteOffset", 0), length = view.get<std::size_t>("byteLength");
    if (offset > bin.size() || length > bin.size() - offset) throw std::out_of_range("the Draco buffer view runs past the BIN chunk");
    const auto decoded = decode_stream(bin.substr(offset, length), path);
    const auto color_id = draco.get_optional<int>("attributes.COLOR_0");
    const auto normal_id = draco.get_optional<int>("attributes.NORMAL");
    return to_mesh(*decoded, decoded->GetAttributeByUniqueId(draco.get<int>("attributes.POSITION")),
                   color_id ? decoded->GetAttributeByUniqueId(*color_id) : nullptr,
                   normal_id ? decoded->GetAttributeByUniqueId(*normal_id) : nullptr, path);
}

// An accessor's elements as `components` doubles each (normalized integers scaled to 0..1).
std::vector<double> accessor_values(const Json& gltf, std::size_t index, int components, std::string_view bin) {
    const Json& accessor = element(gltf.get_child("accessors"), index, "accessors");
    const Json& view = element(gltf.get_child("bufferViews"), accessor.get<std::size_t>("bufferView"), "bufferViews");
    if (view.get<int>("buffer") != 0) throw std::out_of_range("a buffer view is not in the GLB's BIN chunk");
    const int type = accessor.get<int>("componentType");
    const std::size_t size = type == 5126 || type == 5125 ? 4 : type == 5123 ? 2 : type == 5121 ? 1 : 0;
    if (!size) throw std::out_of_range("an accessor's componentType is not float or unsigned");
    const std::size_t count = accessor.get<std::size_t>("count");
    const std::size_t stride = view.get<std::size_t>("byteStride", size * components);
    const std::size_t start = view.get<std::size_t>("byteOffset", 0) + accessor.get<std::size_t>("byteOffset", 0);
    const std::size_t length = view.get<std::size_t>("byteLength");
    if (view.get<std::size_t>("byteOffset", 0) + length > bin.size() || (count && start + stride * (count - 1) + size * components > bin.size()))
        throw std::out_of_range("an accessor runs past the BIN chunk");
    const bool normalized = accessor.get<bool>("normalized", false);
    std::vector<double> values(count * components);
    for (std::size_t i = 0; i < count; ++i)
        for (int c = 0; c < components; ++c) {
            const auto* at = reinterpret_cast<const std::byte*>(bin.data() + start + stride * i + size * c);
            double v = type == 5126 ? load_le<float>(at) : type == 5125 ? load_le<std::uint32_t>(at)
                     : type == 5123 ? load_le<std::uint16_t>(at) : double(load_le<std::uint8_t>(at));
            if (normalized && type == 5123) v /= 65535;
            if (normalized && type == 5121) v /= 255;
            values[i * components + c] = v;
        }
    return values;
}

// A plain primitive: POSITION, NORMAL, COLOR_0 (linear, back to 8-bit sRGB) and the indices.
Mesh plain_primitive(const Json& gltf, const Json& primitive, std::string_view bin) {
    Mesh mesh;
    const std::vector<double> p = accessor_values(gltf, primitive.get<std::size_t>("attributes.POSITION"), 3, bin);
    const std::size_t n = p.size() / 3;
    mesh.positions.resize(n);
    for (std::size_t i = 0; i < n; ++i) mesh.positions[i] = {float(p[3 * i]), float(p[3 * i + 1]), float(p[3 * i + 2])};
    if (const auto id = primitive.get_optional<std::size_t>("attributes.NORMAL")) {
        const std::vector<double> v = accessor_values(gltf, *id, 3, bin);
        if (v.size() != p.size()) throw std::out_of_range("NORMAL and POSITION counts differ");
        mesh.normals.resize(n);
        for (std::size_t i = 0; i < n; ++i) mesh.normals[i] = {float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2])};
    }
    if (const auto id = primitive.get_optional<std::size_t>("attributes.COLOR_0")) {
        const std::vector<double> v = accessor_values(gltf, *id, 3, bin);
        if (v.size() != p.size()) throw std::out_of_range("COLOR_0 and POSITION counts differ");
        mesh.colors.resize(n);
        for (std::size_t i = 0; i < 3 * n; ++i)
            mesh.colors[i / 3][i % 3] = linear16_to_srgb8(static_cast<std::uint16_t>(std::lround(std::clamp(v[i], 0.0, 1.0) * 65535)));
    }
    const std::vector<double> index = accessor_values(gltf, primitive.get<std::size_t>("indices"), 1, bin);
    if (index.size() % 3) throw std::out_of_range("the index count is not a multiple of 3");
    mesh.triangles.resize(index.size() / 3);
    for (std::size_t i = 0; i < index.size(); ++i) {
        if (!(index[i] < double(n))) throw std::out_of_range("a vertex index is not below the vertex count");
        mesh.triangles[i / 3][i % 3] = static_cast<std::uint32_t>(index[i]);
    }
    return mesh;
}

} // namespace

Mesh decode_draco(std::string_view bytes, const std::string& name) {
    const auto decoded = decode_stream(bytes, name);
    return to_mesh(*decoded, decoded->GetNamedAttribute(draco::GeometryAttribute::POSITION),
                   decoded->GetNamedAttribute(draco::GeometryAttribute::COLOR),
                   decoded->GetNamedAttribute(draco::GeometryAttribute::NORMAL), name);
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
        const auto draco = primitive.get_child_optional("extensions.KHR_draco_mesh_compression");
        Mesh mesh = draco ? draco_primitive(gltf, *draco, bin, path) : plain_primitive(gltf, primitive, bin);

        // The origin: the node's extras when present (the mesh stays local then, even with a
        // translation), else its translation, in glTF's Y-up axes (see write_glb): turned back.
        const Json& node = element(gltf.get_child("nodes"), 0, "nodes");
        if (const auto origin = node.get_child_optional("extras.origin")) {
            const std::vector<double> o = numbers(*origin);
            if (o.size() != 3) throw std::out_of_range("the node's extras.origin is not 3 numbers");
            mesh.origin = {o[0], o[1], o[2]};
            mesh.cell_size = node.get<double>("extras.cell_size", 0);
            return mesh;
        }
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
