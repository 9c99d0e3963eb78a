// SPDX-License-Identifier: Apache-2.0
#include "tileset_info.hpp"

#include "byte_order.hpp"
#include "io/json.hpp"
#include "lasmesh/error.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <vector>

namespace lasmesh::cli {

namespace fs = std::filesystem;

namespace {

struct Level {
    std::uint64_t tiles = 0, contents = 0, triangles = 0, bytes = 0;
    double error_min = INFINITY, error_max = -INFINITY;
};

// Triangles of a .glb content: the index counts of its triangle primitives, over 3; 0 for
// anything else (another content type, a missing file).
std::uint64_t glb_triangles(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::array<std::byte, 20> head{};
    if (!in.read(reinterpret_cast<char*>(head.data()), head.size())) return 0;
    if (load_le<std::uint32_t>(head.data()) != 0x46546C67 || load_le<std::uint32_t>(head.data() + 16) != 0x4E4F534A)
        return 0; // "glTF", then a JSON chunk
    std::string text(load_le<std::uint32_t>(head.data() + 12), '\0');
    if (!in.read(text.data(), static_cast<std::streamsize>(text.size()))) return 0;
    const Json gltf = Json::parse(text, nullptr, false);
    if (gltf.is_discarded() || !gltf.contains("meshes")) return 0;
    std::uint64_t triangles = 0;
    for (const Json& mesh : gltf["meshes"])
        for (const Json& primitive : mesh.value("primitives", Json::array()))
            if (primitive.value("mode", 4) == 4 && primitive.contains("indices"))
                triangles += gltf["accessors"][primitive["indices"].get<std::size_t>()].value("count", 0ull) / 3;
    return triangles;
}

void walk(const Json& node, const fs::path& folder, std::size_t depth, std::vector<Level>& levels) {
    if (levels.size() <= depth) levels.resize(depth + 1);
    Level& level = levels[depth];
    ++level.tiles;
    const double error = node.value("geometricError", 0.0);
    level.error_min = std::min(level.error_min, error), level.error_max = std::max(level.error_max, error);
    if (node.contains("content")) {
        const Json& content = node["content"];
        const fs::path file = folder / content.value("uri", content.value("url", std::string()));
        ++level.contents;
        std::error_code missing;
        const std::uintmax_t size = fs::file_size(file, missing);
        level.bytes += missing ? 0 : size;
        level.triangles += glb_triangles(file);
    }
    for (const Json& child : node.value("children", Json::array())) walk(child, folder, depth + 1, levels);
}

} // namespace

bool is_tileset_path(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".json";
}

void write_tileset_info(const std::string& path, bool as_json, std::ostream& out) {
    std::ifstream in(path);
    if (!in) throw_input_error(path, "cannot be opened");
    Json tileset;
    try {
        tileset = Json::parse(in);
    } catch (const Json::parse_error& e) {
        throw_input_error(path, std::string("not valid JSON: ") + e.what());
    }
    if (!tileset.is_object() || !tileset.contains("asset") || !tileset.contains("root") || !tileset["root"].is_object())
        throw_input_error(path, "not a 3D Tiles tileset: it needs an \"asset\" and a \"root\" object");
    std::vector<Level> levels;
    const fs::path folder = fs::path(path).parent_path();
    walk(tileset["root"], folder, 0, levels);
    const Json& root = tileset["root"];
    const bool placed = root.contains("transform");
    const std::string version = tileset["asset"].value("version", "");
    const std::string generator = tileset["asset"].value("generator", "");
    const Json lasmesh = tileset.contains("extras") ? tileset["extras"].value("lasmesh", Json()) : Json();
    if (as_json) {
        Json report;
        report["tileset"] = path;
        report["version"] = version;
        report["generator"] = generator;
        report["placed"] = placed;
        report["crs"] = lasmesh.is_object() ? lasmesh.value("crs", "") : "";
        report["geometric_error"] = tileset.value("geometricError", 0.0);
        report["levels"] = Json::array();
        for (const Level& l : levels)
            report["levels"].push_back({{"tiles", l.tiles},
                                        {"contents", l.contents},
                                        {"triangles", l.triangles},
                                        {"bytes", l.bytes},
                                        {"geometric_error_min", l.error_min},
                                        {"geometric_error_max", l.error_max}});
        out << json_line(report) << '\n';
        return;
    }
    out << "tileset              " << path << " (3D Tiles " << version
        << (generator.empty() ? "" : ", written by " + generator) << ")\n";
    out << "placed               "
        << (placed ? "on the globe (the root has a transform)" : "no: the root has no transform") << '\n';
    if (lasmesh.is_object() && lasmesh.contains("centre"))
        out << "centre               " << format_double(lasmesh["centre"][0].get<double>()) << " E, "
            << format_double(lasmesh["centre"][1].get<double>()) << " N\n";
    if (lasmesh.is_object() && !lasmesh.value("crs", std::string()).empty())
        out << "crs                  " << lasmesh.value("crs", std::string()) << '\n';
    out << "geometric error      " << format_double(tileset.value("geometricError", 0.0)) << " (the tileset's)\n";
    out << "level  tiles  contents  triangles       bytes  geometric error\n";
    for (std::size_t k = 0; k < levels.size(); ++k) {
        const Level& l = levels[k];
        out << std::setw(5) << k << std::setw(7) << l.tiles << std::setw(10) << l.contents << std::setw(11)
            << l.triangles << std::setw(12) << l.bytes << "  " << format_double(l.error_min);
        if (l.error_max != l.error_min) out << " to " << format_double(l.error_max);
        out << '\n';
    }
}

} // namespace lasmesh::cli
