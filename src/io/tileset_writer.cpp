// SPDX-License-Identifier: Apache-2.0
#include "io/tileset_writer.hpp"

#include "io/globe_frame.hpp"
#include "io/json.hpp"
#include "lasmesh/error.hpp"
#include "mesh/mesh_tiles.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <random>

namespace lasmesh {

namespace fs = std::filesystem;

namespace {

// FNV-1a, 64 bits: names the contents' folder after what it holds.
void hash_bytes(std::uint64_t& hash, const std::string& bytes) {
    for (const char c : bytes) {
        hash ^= static_cast<unsigned char>(c);
        hash *= 0x100000001b3ULL;
    }
}

std::string hex16(std::uint64_t value) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
    return text;
}

struct TileBox {
    Vec3 min{INFINITY, INFINITY, INFINITY}, max{-INFINITY, -INFINITY, -INFINITY};
    bool empty() const { return min[0] > max[0]; }
    void add(const Vec3& p) {
        for (int a = 0; a < 3; ++a) min[a] = std::min(min[a], p[a]), max[a] = std::max(max[a], p[a]);
    }
    void add(const TileBox& b) {
        if (!b.empty()) add(b.min), add(b.max);
    }
    double diagonal() const { return empty() ? 0 : std::hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]); }
    // 3D Tiles' box: the centre, then the half axes; never flat (a tile of a flat deck has no height).
    Json json() const {
        constexpr double least_half = 0.0005;
        Json box = Json::array();
        for (int a = 0; a < 3; ++a) box.push_back((min[a] + max[a]) / 2);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) box.push_back(a == b ? std::max((max[a] - min[a]) / 2, least_half) : 0.0);
        return box;
    }
};

struct TileNode {
    TileBox box;
    std::string uri; // empty: no content of its own
};
using TileKey = std::pair<std::int64_t, std::int64_t>; // (y, x)

// A temporary folder removed with its contents unless released.
struct TemporaryFolder {
    fs::path path;
    ~TemporaryFolder() {
        std::error_code ignored;
        if (!path.empty()) fs::remove_all(path, ignored);
    }
};

void write_file(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw Error(ErrorKind::output, path.string() + ": cannot write this tile (is the disk full?)");
}

Json node_json(const std::vector<std::map<TileKey, TileNode>>& levels, const std::vector<double>& errors,
               std::size_t level, const TileKey& key) {
    const TileNode& node = levels[level].at(key);
    Json json;
    json["boundingVolume"] = {{"box", node.box.json()}};
    json["geometricError"] = errors[level];
    if (!node.uri.empty()) json["content"] = {{"uri", node.uri}};
    if (level + 1 < levels.size()) {
        Json children = Json::array();
        for (const auto& [child, _] : levels[level + 1])
            if (child.first >> 1 == key.first && child.second >> 1 == key.second)
                children.push_back(node_json(levels, errors, level + 1, child));
        if (!children.empty()) json["children"] = std::move(children);
    }
    return json;
}

} // namespace

WrittenTileset write_tileset(const std::vector<TilesetLevel>& levels, const TilesetLattice& lattice,
                             const TilesetContent& content, OutputFile& json) {
    WrittenTileset written;
    const fs::path json_path(json.path());
    const fs::path folder = json_path.parent_path().empty() ? fs::path(".") : json_path.parent_path();
    const std::string stem = json_path.stem().string();

    // The frame: east-north-up at the centre of the finest level, or the data's own units around it.
    TileBox world;
    for (const auto& p : levels.back().mesh->positions)
        world.add(Vec3{levels.back().mesh->origin[0] + p[0], levels.back().mesh->origin[1] + p[1],
                       levels.back().mesh->origin[2] + p[2]});
    const Vec3 centre{(world.min[0] + world.max[0]) / 2, (world.min[1] + world.max[1]) / 2,
                      (world.min[2] + world.max[2]) / 2};
    std::unique_ptr<GlobeFrame> frame;
    double metres = 1; // per unit of the CRS: geometric errors are in metres on the globe
    if (content.crs && content.crs->identified()) {
        frame = std::make_unique<GlobeFrame>(*content.crs, centre);
        metres = content.crs->unit_metres > 0 ? content.crs->unit_metres : 1;
    } else {
        written.note =
            content.crs ? "its coordinate system is not identified" : "the input declares no coordinate system";
    }

    // Errors in metres, never smaller than a finer level's (a parent is never the better one).
    std::vector<double> errors(levels.size());
    for (std::size_t k = levels.size(); k-- > 0;)
        errors[k] = std::max(levels[k].error * metres, k + 1 < levels.size() ? errors[k + 1] : 0.0);

    TemporaryFolder temporary;
    std::random_device random;
    temporary.path = folder / (".lasmesh-tiles-" + hex16((std::uint64_t{random()} << 32) | random()) + ".tmp");
    std::error_code failed;
    if (!fs::create_directory(temporary.path, failed))
        throw Error(ErrorKind::output,
                    temporary.path.string() + ": cannot create the tiles' folder: " + failed.message());

    std::uint64_t hash = 0xcbf29ce484222325ULL;
    std::vector<std::map<TileKey, TileNode>> nodes(levels.size());
    for (std::size_t k = 0; k < levels.size(); ++k) {
        const double edge = lattice.root_edge / std::ldexp(1.0, static_cast<int>(k));
        std::vector<MeshTile> tiles =
            split_into_tiles(*levels[k].mesh, lattice.corner, edge, std::int64_t{1} << static_cast<int>(k));
        fs::create_directory(temporary.path / std::to_string(k), failed);
        std::size_t triangles = 0;
        for (MeshTile& tile : tiles) {
            Mesh& m = tile.mesh;
            if (frame) {
                mesh_to_frame(m, *frame);
                m.crs.clear(); // the tile's own extras: east-north-up metres, not the survey's CRS
            } else {           // around the centre, in the data's units; the tile's extras give the centre
                for (auto& p : m.positions)
                    for (int a = 0; a < 3; ++a) p[a] = static_cast<float>(double(p[a]) + m.origin[a] - centre[a]);
                m.origin = centre;
            }
            const std::string name = std::to_string(tile.x) + "_" + std::to_string(tile.y);
            const std::string relative = std::to_string(k) + "/" + name + ".glb";
            GltfOptions glb = content.glb;
            glb.name = std::to_string(k) + "_" + name;
            const std::string bytes = encode_glb(m, glb);
            hash_bytes(hash, relative);
            hash_bytes(hash, bytes);
            write_file(temporary.path / relative, bytes);
            written.content_bytes += bytes.size();
            triangles += m.triangles.size();
            TileNode& node = nodes[k][{tile.y, tile.x}];
            for (const auto& p : m.positions) node.box.add(Vec3{p[0], p[1], p[2]});
            node.uri = relative;
        }
        written.tiles.push_back(tiles.size());
        written.triangles.push_back(triangles);
    }
    // Every tile's parent exists (perhaps without content) and its box holds the children's.
    for (std::size_t k = levels.size(); k-- > 1;)
        for (const auto& [key, node] : nodes[k]) nodes[k - 1][{key.first >> 1, key.second >> 1}].box.add(node.box);
    if (nodes[0].size() != 1)
        throw Error(ErrorKind::output, json.path() + ": the root level has " + std::to_string(nodes[0].size()) +
                                           " tiles, expected one (the lattice is too fine for the data)");

    written.folder = stem + "-" + hex16(hash);
    const fs::path final_folder = folder / written.folder;
    if (fs::exists(final_folder)) {
        // The same bytes from an earlier run (the name is their hash): keep that one.
    } else {
        fs::rename(temporary.path, final_folder, failed);
        if (failed)
            throw Error(ErrorKind::output,
                        final_folder.string() + ": cannot rename the tiles' folder into place: " + failed.message());
        temporary.path.clear();
        written.folder_created = true;
    }
    for (std::size_t k = 0; k < levels.size(); ++k)
        for (auto& [key, node] : nodes[k])
            if (!node.uri.empty()) node.uri = written.folder + "/" + node.uri;

    Json tileset;
    tileset["asset"] = {{"version", "1.1"}, {"generator", "lasmesh"}};
    const TileKey root_key = nodes[0].begin()->first;
    Json root = node_json(nodes, errors, 0, root_key);
    root["refine"] = "REPLACE";
    if (frame) root["transform"] = frame->matrix();
    tileset["geometricError"] = std::max(nodes[0].begin()->second.box.diagonal(), errors[0]);
    Json extras;
    extras["crs"] = content.crs ? crs_for_outputs(*content.crs) : "";
    if (frame) {
        extras["centre"] = {frame->longitude(), frame->latitude()};
    } else {
        extras["origin"] = centre; // add it to a tile's positions for the data's coordinates
        extras["note"] = "not placed on the globe: " + written.note;
    }
    Json per_level = Json::array();
    for (std::size_t k = 0; k < levels.size(); ++k)
        per_level.push_back({{"cell_size", levels[k].mesh->cell_size},
                             {"tile_size", lattice.root_edge / std::ldexp(1.0, static_cast<int>(k))},
                             {"tiles", written.tiles[k]},
                             {"triangles", written.triangles[k]},
                             {"geometric_error", errors[k]}});
    extras["levels"] = std::move(per_level);
    tileset["extras"] = {{"lasmesh", std::move(extras)}};
    tileset["root"] = std::move(root);
    json.write(json_text(tileset));
    written.geometric_error = errors;
    return written;
}

void remove_earlier_tiles(const std::string& json_path, const std::string& kept_folder) {
    const fs::path path(json_path);
    const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    const std::string prefix = path.stem().string() + "-";
    // Ours: NAME- and 16 lower-case hexadecimal digits, as write_tileset names them.
    const auto ours = [&](const std::string& name) {
        return name.size() == prefix.size() + 16 && name.compare(0, prefix.size(), prefix) == 0 &&
               std::all_of(name.begin() + static_cast<std::ptrdiff_t>(prefix.size()), name.end(),
                           [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
    };
    std::error_code ignored;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder, ignored)) {
        const std::string name = entry.path().filename().string();
        if (name != kept_folder && entry.is_directory(ignored) && ours(name)) fs::remove_all(entry.path(), ignored);
    }
}

} // namespace lasmesh
