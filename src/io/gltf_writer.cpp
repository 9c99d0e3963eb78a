// SPDX-License-Identifier: Apache-2.0
// The GLB container: a JSON chunk (padded with spaces) and a BIN chunk (padded with zeros). Plain
// files hold the vertex arrays and the indices in the BIN chunk, one buffer view each; Draco
// files hold only the Draco stream there, and their accessors have no buffer view. Draco's own
// glTF encoder (1.5.5) is not used: it cannot write 16-bit COLOR_0, and node transforms need its
// Scene API, whose headers need Eigen.
#include "io/gltf_writer.hpp"

#include "byte_order.hpp"
#include "io/draco_reader.hpp"
#include "io/json.hpp"
#include "io/output_file.hpp"
#include "io/srgb.hpp"
#include "lasmesh/error.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace lasmesh {

namespace {

constexpr int float_type = 5126, uint16_type = 5123, uint32_type = 5125;

// A float as the double whose shortest text is the float's shortest text (0.1f as 0.1, not
// 0.10000000149011612): the same float reads back, in fewer bytes.
double float_value(float value) {
    char text[32];
    const char* end = std::to_chars(text, text + sizeof text, value).ptr;
    double exact = 0;
    std::from_chars(text, end, exact);
    return exact;
}

bool small_indices(const Mesh& mesh) {
    return mesh.positions.size() <= 65535;
} // 65535 is restart

// What the accessors describe: the mesh itself (plain), or the decoded Draco mesh, whose vertex
// order and count may differ from the encoded one. glTF requires POSITION's bounds.
Json position_accessor(const Mesh& m) {
    Json lo = Json::array(), hi = Json::array();
    for (int c = 0; c < 3; ++c) {
        float low = m.positions[0][c], high = low;
        for (const auto& p : m.positions) low = std::min(low, p[c]), high = std::max(high, p[c]);
        lo.push_back(float_value(low)), hi.push_back(float_value(high));
    }
    return {{"componentType", float_type}, {"count", m.positions.size()}, {"type", "VEC3"}, {"min", lo}, {"max", hi}};
}

struct Layout {
    Json attributes = Json::object(), accessors = Json::array(), views = Json::array();
    Json primitive_extensions; // null when none
    bool draco = false;
    std::string bin;
    std::size_t indices = 0; // the accessor of the indices, after those of the attributes
};

// Vertex arrays and indices in the BIN chunk, each a 4-byte aligned buffer view.
Layout plain_layout(const Mesh& mesh) {
    Layout l;
    const std::size_t n = mesh.positions.size();
    // An accessor on a new buffer view holding `bytes`, the view first in the accessor's keys.
    auto add = [&](const std::string& attribute, const std::string& bytes, int target, int stride, Json accessor) {
        Json view = {{"buffer", 0}, {"byteOffset", l.bin.size()}, {"byteLength", bytes.size()}};
        if (stride) view["byteStride"] = stride;
        view["target"] = target;
        Json with_view = {{"bufferView", l.views.size()}};
        with_view.update(accessor);
        l.views.push_back(view);
        l.bin += bytes;
        l.bin.resize((l.bin.size() + 3) / 4 * 4, '\0');
        if (!attribute.empty()) l.attributes[attribute] = l.accessors.size();
        l.accessors.push_back(with_view);
    };
    auto floats = [&](const std::vector<std::array<float, 3>>& values) {
        std::string bytes(12 * values.size(), '\0');
        for (std::size_t i = 0; i < values.size(); ++i)
            for (int c = 0; c < 3; ++c)
                store_le<float>(reinterpret_cast<std::byte*>(bytes.data() + 12 * i + 4 * c), values[i][c]);
        return bytes;
    };
    add("POSITION", floats(mesh.positions), 34962, 0, position_accessor(mesh));
    if (!mesh.normals.empty())
        add("NORMAL", floats(mesh.normals), 34962, 0, {{"componentType", float_type}, {"count", n}, {"type", "VEC3"}});
    if (!mesh.colors.empty()) {
        std::string bytes(8 * n, '\0'); // three words and two bytes of padding per vertex
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c)
                store_le<std::uint16_t>(reinterpret_cast<std::byte*>(bytes.data() + 8 * i + 2 * c),
                                        srgb8_to_linear16(mesh.colors[i][c]));
        add("COLOR_0", bytes, 34962, 8,
            {{"componentType", uint16_type}, {"normalized", true}, {"count", n}, {"type", "VEC3"}});
    }
    l.indices = l.accessors.size();
    const bool small = small_indices(mesh);
    const std::size_t width = small ? 2 : 4;
    std::string bytes(width * 3 * mesh.triangles.size(), '\0');
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) {
            auto* at = reinterpret_cast<std::byte*>(bytes.data() + width * (3 * t + c));
            if (small)
                store_le<std::uint16_t>(at, static_cast<std::uint16_t>(mesh.triangles[t][c]));
            else
                store_le<std::uint32_t>(at, mesh.triangles[t][c]);
        }
    add("", bytes, 34963, 0,
        {{"componentType", small ? uint16_type : uint32_type}, {"count", bytes.size() / width}, {"type", "SCALAR"}});
    return l;
}

// The Draco stream alone in the BIN chunk; accessors without buffer views.
Layout draco_layout(const Mesh& mesh, const DracoOptions& options) {
    Layout l;
    l.draco = true;
    l.bin = encode_draco(mesh, options, DracoColor::linear16);
    Mesh decoded;
    try {
        decoded = decode_draco(l.bin, "the Draco stream just encoded");
    } catch (const Error& e) {
        throw Error(ErrorKind::output, e.what()); // a Draco bug: not the user's input
    }
    if (decoded.positions.empty()) throw Error(ErrorKind::output, "the Draco stream holds no vertices");
    const std::size_t points = decoded.positions.size();
    Json ids = {{"POSITION", draco_position_id}};
    l.attributes["POSITION"] = 0;
    l.accessors.push_back(position_accessor(decoded));
    if (!decoded.colors.empty()) {
        ids["COLOR_0"] = draco_color_id;
        l.attributes["COLOR_0"] = l.accessors.size();
        l.accessors.push_back(
            {{"componentType", uint16_type}, {"normalized", true}, {"count", points}, {"type", "VEC3"}});
    }
    if (!decoded.normals.empty()) {
        ids["NORMAL"] = draco_normal_id;
        l.attributes["NORMAL"] = l.accessors.size();
        l.accessors.push_back({{"componentType", float_type}, {"count", points}, {"type", "VEC3"}});
    }
    l.indices = l.accessors.size();
    l.accessors.push_back({{"componentType", small_indices(decoded) ? uint16_type : uint32_type},
                           {"count", 3 * decoded.triangles.size()},
                           {"type", "SCALAR"}});
    l.views.push_back({{"buffer", 0}, {"byteOffset", 0}, {"byteLength", l.bin.size()}});
    l.primitive_extensions = {{"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", ids}}}};
    return l;
}

std::string gltf_json(const Mesh& mesh, const GltfOptions& options, const Layout& l, std::size_t bin_bytes) {
    const double h = std::sqrt(0.5);
    const Vec3& o = mesh.origin;
    const Json gltf_origin = {o[0], o[2], -o[1]};
    Json extras = {{"origin", {o[0], o[1], o[2]}}, {"origin_gltf", gltf_origin}};
    if (mesh.cell_size > 0) extras["cell_size"] = mesh.cell_size;
    if (!mesh.crs.empty()) extras["crs"] = mesh.crs;
    // The name comes from a file name: bytes that are not UTF-8 are read as Latin-1 (glTF's JSON
    // must be UTF-8), so "d\xe9ck" is "déck".
    const std::string name = utf8_or_latin1(options.name);

    Json j = {{"asset", {{"version", "2.0"}, {"generator", "lasmesh"}}}};
    if (l.draco) {
        j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
        j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    }
    j["scene"] = 0;
    j["scenes"] = {{{"name", name}, {"nodes", {0}}, {"extras", extras}}};
    Json node = {{"name", name}, {"mesh", 0}, {"rotation", {-h, 0, 0, h}}};
    if (options.origin == GltfOrigin::node) node["translation"] = gltf_origin;
    node["extras"] = extras;
    j["nodes"] = {node};
    Json primitive = {{"attributes", l.attributes}, {"indices", l.indices}, {"material", 0}, {"mode", 4}};
    if (!l.primitive_extensions.is_null()) primitive["extensions"] = l.primitive_extensions;
    j["meshes"] = {{{"name", name}, {"primitives", {primitive}}}};
    j["materials"] = {{{"name", name},
                       {"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 1}}},
                       {"doubleSided", true}}};
    j["accessors"] = l.accessors;
    j["bufferViews"] = l.views;
    j["buffers"] = {{{"byteLength", bin_bytes}}};
    return json_text(j);
}

// A GLB chunk: length, type, data padded to 4 bytes with `pad`.
std::string chunk(std::uint32_t type, std::string data, char pad) {
    data.resize((data.size() + 3) / 4 * 4, pad);
    std::string header(8, '\0');
    store_le<std::uint32_t>(reinterpret_cast<std::byte*>(header.data()), static_cast<std::uint32_t>(data.size()));
    store_le<std::uint32_t>(reinterpret_cast<std::byte*>(header.data() + 4), type);
    return header + data;
}

} // namespace

std::string encode_glb(const Mesh& mesh, const GltfOptions& options) {
    if (mesh.triangles.empty()) throw Error(ErrorKind::output, "the mesh has no triangles, glTF cannot hold it");
    const Layout layout =
        options.compression == GltfCompression::draco ? draco_layout(mesh, options.draco) : plain_layout(mesh);
    if (layout.bin.size() > 0xFFFFFFF0u) throw Error(ErrorKind::output, "the mesh is too large for a GLB file (4 GiB)");
    const std::string body = chunk(0x4E4F534A, gltf_json(mesh, options, layout, layout.bin.size()), ' ') +
                             chunk(0x004E4942, layout.bin, '\0');
    if (body.size() + 12 > 0xFFFFFFFFu) throw Error(ErrorKind::output, "the mesh is too large for a GLB file (4 GiB)");
    std::string header(12, '\0');
    header.replace(0, 4, "glTF");
    store_le<std::uint32_t>(reinterpret_cast<std::byte*>(header.data() + 4), 2);
    store_le<std::uint32_t>(reinterpret_cast<std::byte*>(header.data() + 8),
                            static_cast<std::uint32_t>(12 + body.size()));
    return header + body;
}

void write_glb(const Mesh& mesh, const std::string& path, const GltfOptions& options) {
    write_encoded(path, "glTF", mesh.triangles.empty(), [&] { return encode_glb(mesh, options); });
}

} // namespace lasmesh
