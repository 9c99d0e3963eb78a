// SPDX-License-Identifier: Apache-2.0
// Reading a .glb: the container (12-byte header, JSON chunk, BIN chunk) parsed here, the JSON with
// nlohmann-json, the first mesh's first primitive read plain or through Draco's decoder.
#include "io/gltf_reader.hpp"

#include "byte_order.hpp"
#include "io/json.hpp"
#include "io/mesh_file.hpp"
#include "io/srgb.hpp"
#include "lasmesh/error.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lasmesh {

namespace {

using nlohmann::json;

// Element `index` of the top-level array `name`.
const json& element(const json& gltf, const char* name, std::size_t index) {
    const json& array = gltf.at(name);
    if (!array.is_array() || index >= array.size())
        throw std::out_of_range(std::string(name) + " has no element " + std::to_string(index));
    return array[index];
}

std::vector<double> numbers(const json& array) {
    return array.get<std::vector<double>>();
}

// Whether a node rotation (x, y, z, w) is write_glb's: -90 degrees about x.
bool is_z_up_to_y_up(const std::vector<double>& q) {
    const double h = std::sqrt(0.5);
    return q.size() == 4 && std::abs(q[0] + h) < 1e-9 && std::abs(q[1]) < 1e-9 && std::abs(q[2]) < 1e-9 &&
           std::abs(q[3] - h) < 1e-9;
}

std::optional<int> optional_id(const json& object, const char* key) {
    return object.contains(key) ? std::optional<int>(object.at(key).get<int>()) : std::nullopt;
}

// The primitive's Draco stream, its attributes found by the unique ids the extension names.
Mesh draco_primitive(const json& gltf, const json& draco, std::string_view bin, const std::string& path) {
    const json& view = element(gltf, "bufferViews", draco.at("bufferView").get<std::size_t>());
    if (view.at("buffer").get<int>() != 0)
        throw std::out_of_range("the Draco buffer view is not in the GLB's BIN chunk");
    const std::size_t offset = view.value("byteOffset", std::size_t{0}),
                      length = view.at("byteLength").get<std::size_t>();
    if (offset > bin.size() || length > bin.size() - offset)
        throw std::out_of_range("the Draco buffer view runs past the BIN chunk");
    const json& ids = draco.at("attributes");
    return decode_draco_attributes(bin.substr(offset, length), path, ids.at("POSITION").get<int>(),
                                   optional_id(ids, "COLOR_0"), optional_id(ids, "NORMAL"));
}

// An accessor's elements as `components` doubles each (normalized integers scaled to 0..1).
std::vector<double> accessor_values(const json& gltf, std::size_t index, int components, std::string_view bin) {
    const json& accessor = element(gltf, "accessors", index);
    const json& view = element(gltf, "bufferViews", accessor.at("bufferView").get<std::size_t>());
    if (view.at("buffer").get<int>() != 0) throw std::out_of_range("a buffer view is not in the GLB's BIN chunk");
    const int type = accessor.at("componentType").get<int>();
    const std::size_t size = type == 5126 || type == 5125 ? 4 : type == 5123 ? 2 : type == 5121 ? 1 : 0;
    if (!size) throw std::out_of_range("an accessor's componentType is not float or unsigned");
    const std::size_t count = accessor.at("count").get<std::size_t>();
    const std::size_t stride = view.value("byteStride", size * components);
    const std::size_t view_offset = view.value("byteOffset", std::size_t{0});
    const std::size_t start = view_offset + accessor.value("byteOffset", std::size_t{0});
    const std::size_t length = view.at("byteLength").get<std::size_t>();
    if (view_offset + length > bin.size() || (count && start + stride * (count - 1) + size * components > bin.size()))
        throw std::out_of_range("an accessor runs past the BIN chunk");
    const bool normalized = accessor.value("normalized", false);
    std::vector<double> values(count * components);
    for (std::size_t i = 0; i < count; ++i)
        for (int c = 0; c < components; ++c) {
            const auto* at = reinterpret_cast<const std::byte*>(bin.data() + start + stride * i + size * c);
            double v = type == 5126   ? load_le<float>(at)
                       : type == 5125 ? load_le<std::uint32_t>(at)
                       : type == 5123 ? load_le<std::uint16_t>(at)
                                      : double(load_le<std::uint8_t>(at));
            if (normalized && type == 5123) v /= 65535;
            if (normalized && type == 5121) v /= 255;
            values[i * components + c] = v;
        }
    return values;
}

// A plain primitive: POSITION, NORMAL, COLOR_0 (linear, back to 8-bit sRGB) and the indices.
Mesh plain_primitive(const json& gltf, const json& primitive, std::string_view bin) {
    Mesh mesh;
    const json& attributes = primitive.at("attributes");
    const std::vector<double> p = accessor_values(gltf, attributes.at("POSITION").get<std::size_t>(), 3, bin);
    const std::size_t n = p.size() / 3;
    mesh.positions.resize(n);
    for (std::size_t i = 0; i < n; ++i) mesh.positions[i] = {float(p[3 * i]), float(p[3 * i + 1]), float(p[3 * i + 2])};
    if (attributes.contains("NORMAL")) {
        const std::vector<double> v = accessor_values(gltf, attributes.at("NORMAL").get<std::size_t>(), 3, bin);
        if (v.size() != p.size()) throw std::out_of_range("NORMAL and POSITION counts differ");
        mesh.normals.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            mesh.normals[i] = {float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2])};
    }
    if (attributes.contains("COLOR_0")) {
        const std::vector<double> v = accessor_values(gltf, attributes.at("COLOR_0").get<std::size_t>(), 3, bin);
        if (v.size() != p.size()) throw std::out_of_range("COLOR_0 and POSITION counts differ");
        mesh.colors.resize(n);
        for (std::size_t i = 0; i < 3 * n; ++i)
            mesh.colors[i / 3][i % 3] =
                linear16_to_srgb8(static_cast<std::uint16_t>(std::lround(std::clamp(v[i], 0.0, 1.0) * 65535)));
    }
    const std::vector<double> index = accessor_values(gltf, primitive.at("indices").get<std::size_t>(), 1, bin);
    if (index.size() % 3) throw std::out_of_range("the index count is not a multiple of 3");
    mesh.triangles.resize(index.size() / 3);
    for (std::size_t i = 0; i < index.size(); ++i) {
        if (!(index[i] < double(n))) throw std::out_of_range("a vertex index is not below the vertex count");
        mesh.triangles[i / 3][i % 3] = static_cast<std::uint32_t>(index[i]);
    }
    return mesh;
}

} // namespace

Mesh read_glb(const std::string& path) {
    const std::string file = read_whole_file(path);
    const auto* bytes = reinterpret_cast<const std::byte*>(file.data());
    auto u32 = [&](std::size_t at) { return load_le<std::uint32_t>(bytes + at); };
    if (file.size() < 20 || file.compare(0, 4, "glTF") != 0 || u32(4) != 2)
        throw Error(ErrorKind::input, path + ": not a glTF 2.0 binary file (GLB)");
    if (u32(8) != file.size())
        throw Error(ErrorKind::input, path + ": the GLB header gives " + std::to_string(u32(8)) +
                                          " bytes, the file has " + std::to_string(file.size()));
    const std::size_t json_length = u32(12);
    if (u32(16) != 0x4E4F534A || 20 + json_length > file.size())
        throw Error(ErrorKind::input, path + ": the first GLB chunk is not a complete JSON chunk");
    const std::size_t bin_at = 20 + json_length;
    if (bin_at + 8 > file.size() || u32(bin_at + 4) != 0x004E4942 || bin_at + 8 + u32(bin_at) > file.size())
        throw Error(ErrorKind::input, path + ": no complete BIN chunk after the JSON chunk");
    const std::string_view bin = std::string_view(file).substr(bin_at + 8, u32(bin_at));

    try {
        const json gltf = json::parse(file.begin() + 20, file.begin() + static_cast<std::ptrdiff_t>(bin_at));
        const json& primitive = element(element(gltf, "meshes", 0), "primitives", 0);
        const json* draco = nullptr;
        if (primitive.contains("extensions") && primitive.at("extensions").contains("KHR_draco_mesh_compression"))
            draco = &primitive.at("extensions").at("KHR_draco_mesh_compression");
        Mesh mesh = draco ? draco_primitive(gltf, *draco, bin, path) : plain_primitive(gltf, primitive, bin);

        // The origin: the node's extras when present (the mesh stays local then, even with a
        // translation), else its translation, in glTF's Y-up axes (see write_glb): turned back.
        const json& node = element(gltf, "nodes", 0);
        if (node.contains("extras") && node.at("extras").contains("origin")) {
            const std::vector<double> o = numbers(node.at("extras").at("origin"));
            if (o.size() != 3) throw std::out_of_range("the node's extras.origin is not 3 numbers");
            mesh.origin = {o[0], o[1], o[2]};
            mesh.cell_size = node.at("extras").value("cell_size", 0.0);
            mesh.crs = node.at("extras").value("crs", std::string());
            return mesh;
        }
        const std::vector<double> t =
            node.contains("translation") ? numbers(node.at("translation")) : std::vector<double>{0, 0, 0};
        if (t.size() != 3) throw std::out_of_range("the node's translation is not 3 numbers");
        if (!node.contains("rotation")) {
            mesh.origin = {t[0], t[1], t[2]};
        } else if (is_z_up_to_y_up(numbers(node.at("rotation")))) {
            mesh.origin = {t[0], -t[2], t[1]};
        } else {
            throw std::out_of_range("the node's rotation is not lasmesh's Z-up to Y-up rotation");
        }
        return mesh;
    } catch (const nlohmann::json::exception& e) {
        throw Error(ErrorKind::input, path + ": glTF JSON: " + e.what());
    } catch (const std::out_of_range& e) {
        throw Error(ErrorKind::input, path + ": " + e.what());
    }
}

} // namespace lasmesh
