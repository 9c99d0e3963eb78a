// The GLB container: a JSON chunk (padded with spaces) and a BIN chunk (padded with zeros). Plain
// files hold the vertex arrays and the indices in the BIN chunk, one buffer view each; Draco
// files hold only the Draco stream there, and their accessors have no buffer view. Draco's own
// glTF encoder (1.5.5) is not used: it cannot write 16-bit COLOR_0, and node transforms need its
// Scene API, whose headers need Eigen.
#include "lasmesh/io/gltf_writer.hpp"

#include "lasmesh/byte_order.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/io/draco_reader.hpp"
#include "lasmesh/io/output_file.hpp"
#include "lasmesh/io/srgb.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>

namespace lasmesh {

namespace {

constexpr int float_type = 5126, uint16_type = 5123, uint32_type = 5125;

// Shortest text that reads back as the same number (floats as floats, doubles as doubles).
template <typename T>
std::string number(T value) {
    char text[32];
    return std::string(text, std::to_chars(text, text + sizeof text, value).ptr);
}

template <typename T>
std::string array(const std::vector<T>& values) {
    std::string text = "[";
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (i) text += ',';
        text += number(values[i]);
    }
    return text + ']';
}

// A JSON string: the name comes from a file name, which may hold quotes or control characters.
std::string quoted(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char escape[8];
            std::snprintf(escape, sizeof escape, "\\u%04x", static_cast<unsigned char>(c));
            out += escape;
        } else {
            out += c;
        }
    }
    return out + '"';
}

bool small_indices(const Mesh& mesh) { return mesh.positions.size() <= 65535; } // 65535 is restart

// What the accessors describe: the mesh itself (plain), or the decoded Draco mesh, whose vertex
// order and count may differ from the encoded one.
std::string position_accessor(const Mesh& m, const std::string& view) {
    std::vector<float> lo(3), hi(3);
    for (int c = 0; c < 3; ++c) {
        lo[c] = hi[c] = m.positions[0][c];
        for (const auto& p : m.positions) {
            lo[c] = std::min(lo[c], p[c]);
            hi[c] = std::max(hi[c], p[c]);
        }
    }
    return "{" + view + "\"componentType\":" + std::to_string(float_type) + ",\"count\":" +
           std::to_string(m.positions.size()) + ",\"type\":\"VEC3\",\"min\":" + array(lo) + ",\"max\":" + array(hi) + "}";
}

struct Layout {
    std::string attributes, accessors, views, primitive_extension, extensions;
    std::string bin;
    int indices = 0; // the accessor of the indices, after those of the attributes
};

// Vertex arrays and indices in the BIN chunk, each a 4-byte aligned buffer view.
Layout plain_layout(const Mesh& mesh) {
    Layout l;
    const std::size_t n = mesh.positions.size();
    int view = 0;
    auto add_view = [&](const std::string& bytes, int target, int stride) {
        l.views += (view ? "," : "") + std::string("{\"buffer\":0,\"byteOffset\":") + std::to_string(l.bin.size()) +
                   ",\"byteLength\":" + std::to_string(bytes.size()) +
                   (stride ? ",\"byteStride\":" + std::to_string(stride) : "") + ",\"target\":" + std::to_string(target) + "}";
        l.bin += bytes;
        l.bin.resize((l.bin.size() + 3) / 4 * 4, '\0');
        return "\"bufferView\":" + std::to_string(view++) + ",";
    };
    auto floats = [&](const std::vector<std::array<float, 3>>& values) {
        std::string bytes(12 * values.size(), '\0');
        for (std::size_t i = 0; i < values.size(); ++i)
            for (int c = 0; c < 3; ++c) store_le<float>(reinterpret_cast<std::byte*>(bytes.data() + 12 * i + 4 * c), values[i][c]);
        return bytes;
    };
    int accessor = 0;
    l.attributes = "\"POSITION\":" + std::to_string(accessor++);
    l.accessors = position_accessor(mesh, add_view(floats(mesh.positions), 34962, 0));
    if (!mesh.normals.empty()) {
        l.attributes += ",\"NORMAL\":" + std::to_string(accessor++);
        l.accessors += ",{" + add_view(floats(mesh.normals), 34962, 0) + "\"componentType\":" + std::to_string(float_type) +
                       ",\"count\":" + std::to_string(n) + ",\"type\":\"VEC3\"}";
    }
    if (!mesh.colors.empty()) {
        std::string bytes(8 * n, '\0'); // three words and two bytes of padding per vertex
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c)
                store_le<std::uint16_t>(reinterpret_cast<std::byte*>(bytes.data() + 8 * i + 2 * c), srgb8_to_linear16(mesh.colors[i][c]));
        l.attributes += ",\"COLOR_0\":" + std::to_string(accessor++);
        l.accessors += ",{" + add_view(bytes, 34962, 8) + "\"componentType\":" + std::to_string(uint16_type) +
                       ",\"normalized\":true,\"count\":" + std::to_string(n) + ",\"type\":\"VEC3\"}";
    }
    l.indices = accessor;
    const bool small = small_indices(mesh);
    const std::size_t width = small ? 2 : 4;
    std::string bytes(width * 3 * mesh.triangles.size(), '\0');
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) {
            auto* at = reinterpret_cast<std::byte*>(bytes.data() + width * (3 * t + c));
            if (small) store_le<std::uint16_t>(at, static_cast<std::uint16_t>(mesh.triangles[t][c]));
            else store_le<std::uint32_t>(at, mesh.triangles[t][c]);
        }
    l.accessors += ",{" + add_view(bytes, 34963, 0) + "\"componentType\":" + std::to_string(small ? uint16_type : uint32_type) +
                   ",\"count\":" + std::to_string(bytes.size() / width) + ",\"type\":\"SCALAR\"}";
    return l;
}

// The Draco stream alone in the BIN chunk; accessors without buffer views.
Layout draco_layout(const Mesh& mesh, const DracoOptions& options) {
    Layout l;
    l.bin = encode_draco(mesh, options, DracoColor::linear16);
    Mesh decoded;
    try {
        decoded = decode_draco(l.bin, "the Draco stream just encoded");
    } catch (const Error& e) {
        throw Error(ErrorKind::output, e.what()); // a Draco bug: not the user's input
    }
    if (decoded.positions.empty()) throw Error(ErrorKind::output, "the Draco stream holds no vertices");
    const std::string points = std::to_string(decoded.positions.size());
    const bool color = !decoded.colors.empty(), normal = !decoded.normals.empty();
    std::string ids = "\"POSITION\":" + std::to_string(draco_position_id);
    l.attributes = "\"POSITION\":0";
    l.accessors = position_accessor(decoded, "");
    int accessor = 1;
    if (color) {
        ids += ",\"COLOR_0\":" + std::to_string(draco_color_id);
        l.attributes += ",\"COLOR_0\":" + std::to_string(accessor++);
        l.accessors += ",{\"componentType\":" + std::to_string(uint16_type) + ",\"normalized\":true,\"count\":" + points +
                       ",\"type\":\"VEC3\"}";
    }
    if (normal) {
        ids += ",\"NORMAL\":" + std::to_string(draco_normal_id);
        l.attributes += ",\"NORMAL\":" + std::to_string(accessor++);
        l.accessors += ",{\"componentType\":" + std::to_string(float_type) + ",\"count\":" + points + ",\"type\":\"VEC3\"}";
    }
    l.indices = accessor;
    l.accessors += ",{\"componentType\":" + std::to_string(small_indices(decoded) ? uint16_type : uint32_type) +
                   ",\"count\":" + std::to_string(3 * decoded.triangles.size()) + ",\"type\":\"SCALAR\"}";
    l.views = "{\"buffer\":0,\"byteOffset\":0,\"byteLength\":" + std::to_string(l.bin.size()) + "}";
    l.primitive_extension = ",\"extensions\":{\"KHR_draco_mesh_compression\":{\"bufferView\":0,\"attributes\":{" + ids + "}}}";
    l.extensions = "\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],"
                   "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],";
    return l;
}

std::string json(const Mesh& mesh, const GltfOptions& options, const Layout& l, std::size_t bin_bytes) {
    const double h = std::sqrt(0.5);
    const Vec3& o = mesh.origin;
    const std::vector<double> gltf_origin{o[0], o[2], -o[1]};
    std::string extras = "\"extras\":{\"origin\":" + array(std::vector<double>{o[0], o[1], o[2]}) +
                         ",\"origin_gltf\":" + array(gltf_origin);
    if (mesh.cell_size > 0) extras += ",\"cell_size\":" + number(mesh.cell_size);
    extras += "}";
    const std::string name = "\"name\":" + quoted(options.name);

    std::string j = "{\"asset\":{\"version\":\"2.0\",\"generator\":\"lasmesh\"},";
    j += l.extensions;
    j += "\"scene\":0,\"scenes\":[{" + name + ",\"nodes\":[0]," + extras + "}],";
    j += "\"nodes\":[{" + name + ",\"mesh\":0,\"rotation\":" + array(std::vector<double>{-h, 0, 0, h});
    if (options.origin == GltfOrigin::node) j += ",\"translation\":" + array(gltf_origin);
    j += "," + extras + "}],";
    j += "\"meshes\":[{" + name + ",\"primitives\":[{\"attributes\":{" + l.attributes + "},\"indices\":" +
         std::to_string(l.indices) + ",\"material\":0,\"mode\":4" +
         l.primitive_extension + "}]}],";
    j += "\"materials\":[{" + name + ",\"pbrMetallicRoughness\":{\"metallicFactor\":0,\"roughnessFactor\":1},\"doubleSided\":true}],";
    j += "\"accessors\":[" + l.accessors + "],";
    j += "\"bufferViews\":[" + l.views + "],";
    j += "\"buffers\":[{\"byteLength\":" + std::to_string(bin_bytes) + "}]}";
    return j;
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
    const Layout layout = options.compression == GltfCompression::draco ? draco_layout(mesh, options.draco) : plain_layout(mesh);
    if (layout.bin.size() > 0xFFFFFFF0u) throw Error(ErrorKind::output, "the mesh is too large for a GLB file (4 GiB)");
    const std::string body =
        chunk(0x4E4F534A, json(mesh, options, layout, layout.bin.size()), ' ') + chunk(0x004E4942, layout.bin, '\0');
    if (body.size() + 12 > 0xFFFFFFFFu) throw Error(ErrorKind::output, "the mesh is too large for a GLB file (4 GiB)");
    std::string header(12, '\0');
    header.replace(0, 4, "glTF");
    store_le<std::uint32_t>(reinterpret_cast<std::byte*>(header.data() + 4), 2);
    store_le<std::uint32_t>(reinterpret_cast<std::byte*>(header.data() + 8), static_cast<std::uint32_t>(12 + body.size()));
    return header + body;
}

void write_glb(const Mesh& mesh, const std::string& path, const GltfOptions& options) {
    write_encoded(path, "glTF", mesh.triangles.empty(), [&] { return encode_glb(mesh, options); });
}

} // namespace lasmesh
