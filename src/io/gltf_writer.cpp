// The GLB container around a Draco stream: a JSON chunk (padded with spaces) and a BIN chunk
// (padded with zeros) holding only the stream. Draco's own glTF encoder (1.5.5) is not used: it
// cannot write 16-bit COLOR_0, and node transforms need its Scene API, whose headers need Eigen.
#include "lasmesh/io/gltf_writer.hpp"

#include "lasmesh/byte_order.hpp"
#include "lasmesh/io/draco_reader.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/io/output_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace lasmesh {

namespace {

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

std::string json(const Mesh& decoded, const Vec3& origin, std::size_t draco_bytes) {
    // Accessors without bufferView: their data is the decoded Draco stream, so the counts and the
    // bounds (required for POSITION) are those of the decoded mesh, which Draco may have reordered.
    std::vector<float> lo(3), hi(3);
    for (int c = 0; c < 3; ++c) {
        lo[c] = hi[c] = decoded.positions[0][c];
        for (const auto& p : decoded.positions) {
            lo[c] = std::min(lo[c], p[c]);
            hi[c] = std::max(hi[c], p[c]);
        }
    }
    const bool color = !decoded.colors.empty();
    const std::string points = std::to_string(decoded.positions.size());
    const std::string attributes =
        std::string("{\"POSITION\":") + std::to_string(draco_position_id) +
        (color ? ",\"COLOR_0\":" + std::to_string(draco_color_id) : "") + "}";
    const std::string accessor_ids = color ? "{\"POSITION\":0,\"COLOR_0\":1}" : "{\"POSITION\":0}";
    const int indices = color ? 2 : 1;
    const double h = std::sqrt(0.5);

    std::string j = "{\"asset\":{\"version\":\"2.0\",\"generator\":\"lasmesh\"},";
    j += "\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],";
    j += "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],";
    j += "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],";
    j += "\"nodes\":[{\"mesh\":0,\"rotation\":" + array(std::vector<double>{-h, 0, 0, h}) + ",\"translation\":" +
         array(std::vector<double>{origin[0], origin[2], -origin[1]}) + "}],";
    j += "\"meshes\":[{\"primitives\":[{\"attributes\":" + accessor_ids + ",\"indices\":" + std::to_string(indices) +
         ",\"material\":0,\"mode\":4,\"extensions\":{\"KHR_draco_mesh_compression\":{\"bufferView\":0,\"attributes\":" +
         attributes + "}}}]}],";
    j += "\"materials\":[{\"pbrMetallicRoughness\":{\"metallicFactor\":0,\"roughnessFactor\":1}}],";
    j += "\"accessors\":[{\"componentType\":5126,\"count\":" + points + ",\"type\":\"VEC3\",\"min\":" + array(lo) +
         ",\"max\":" + array(hi) + "},";
    if (color) j += "{\"componentType\":5123,\"normalized\":true,\"count\":" + points + ",\"type\":\"VEC3\"},";
    j += "{\"componentType\":5125,\"count\":" + std::to_string(3 * decoded.triangles.size()) + ",\"type\":\"SCALAR\"}],";
    j += "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":" + std::to_string(draco_bytes) + "}],";
    j += "\"buffers\":[{\"byteLength\":" + std::to_string(draco_bytes) + "}]}";
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

std::string encode_glb(const Mesh& mesh, const DracoOptions& options) {
    const std::string draco = encode_draco(mesh, options, DracoColor::linear16);
    Mesh decoded;
    try {
        decoded = decode_draco(draco, "the Draco stream just encoded");
    } catch (const Error& e) {
        throw Error(ErrorKind::output, e.what()); // a Draco bug: not the user's input
    }
    if (decoded.positions.empty()) throw Error(ErrorKind::output, "the Draco stream holds no vertices");
    const std::string body = chunk(0x4E4F534A, json(decoded, mesh.origin, draco.size()), ' ') + chunk(0x004E4942, draco, '\0');
    if (body.size() + 12 > 0xFFFFFFFFu) throw Error(ErrorKind::output, "the mesh is too large for a GLB file (4 GiB)");
    std::string header(12, '\0');
    header.replace(0, 4, "glTF");
    store_le<std::uint32_t>(reinterpret_cast<std::byte*>(header.data() + 4), 2);
    store_le<std::uint32_t>(reinterpret_cast<std::byte*>(header.data() + 8), static_cast<std::uint32_t>(12 + body.size()));
    return header + body;
}

void write_glb(const Mesh& mesh, const std::string& path, const DracoOptions& options) {
    write_encoded(path, "glTF", mesh.triangles.empty(), [&] { return encode_glb(mesh, options); });
}

} // namespace lasmesh
