// SPDX-License-Identifier: Apache-2.0
#include "io/html_writer.hpp"

#include "byte_order.hpp"
#include "io/json.hpp"
#include "lasmesh/error.hpp"

#include <boost/archive/iterators/base64_from_binary.hpp>
#include <boost/archive/iterators/transform_width.hpp>
#include <meshoptimizer.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lasmesh {

namespace {

std::string base64(std::string_view bytes) {
    using namespace boost::archive::iterators;
    using Encoder = base64_from_binary<transform_width<std::string_view::const_iterator, 6, 8>>;
    std::string text(Encoder(bytes.begin()), Encoder(bytes.end()));
    text.append((3 - bytes.size() % 3) % 3, '=');
    return text;
}

std::string zlib_compress(const std::string& bytes) {
    uLongf size = compressBound(static_cast<uLong>(bytes.size()));
    std::string out(size, '\0');
    if (compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(bytes.data()),
                  static_cast<uLong>(bytes.size()), 9) != Z_OK)
        throw Error(ErrorKind::output, "zlib could not compress the page's mesh");
    out.resize(size);
    return out;
}

// The step of the positions' integers: a power of two no larger than a thousandth of a cell (or
// a millionth of the mesh's extent without a cell size) nor than 0.0001 units (a tenth of a
// millimetre in metres: measurements keep their millimetres), doubled until every coordinate
// fits 31 bits.
double position_step(const Mesh& mesh) {
    double extent = 0;
    for (const auto& p : mesh.positions)
        for (float v : p) extent = std::max(extent, std::abs(double(v)));
    const double relative = mesh.cell_size > 0 ? mesh.cell_size / 1000 : std::max(extent, 1e-9) / (1 << 20);
    const double wanted = std::min(relative, 1e-4);
    double step = std::exp2(std::floor(std::log2(wanted)));
    while (extent / step >= 2147483000.0) step *= 2;
    return step;
}

template <typename T>
std::string encode_vertices(const std::vector<T>& values) {
    std::string out(meshopt_encodeVertexBufferBound(values.size(), sizeof(T)), '\0');
    out.resize(meshopt_encodeVertexBuffer(reinterpret_cast<unsigned char*>(out.data()), out.size(), values.data(),
                                          values.size(), sizeof(T)));
    return out;
}

// Lighter copies of the mesh that the page draws while the camera moves, when drawing the whole
// of it would not keep up (a software renderer, a weak GPU): each a quarter of the one before,
// down to the first of at most `smallest_motion_triangles`. They are triangles on the page's own
// vertices (meshoptimizer's edge collapses keep a subset of them; its vertex clustering where
// those stop short of the quarter), so each costs only its indices. Level of detail while moving
// is what desktop viewers do (VTK's LOD actors, ParaView's interactive decimation).
constexpr std::size_t smallest_motion_triangles = 1000;

std::vector<std::vector<unsigned int>> motion_levels(const std::vector<unsigned int>& indices,
                                                     const std::vector<std::array<float, 3>>& positions) {
    std::vector<std::vector<unsigned int>> levels;
    const std::vector<unsigned int>* finer = &indices;
    while (finer->size() / 3 > smallest_motion_triangles) {
        const std::size_t target = finer->size() / 12 * 3;
        std::vector<unsigned int> level(finer->size());
        const float anywhere = 1.0f; // no bound on the error (relative to the mesh's extent): the count decides
        std::size_t kept = meshopt_simplify(level.data(), finer->data(), finer->size(), positions[0].data(),
                                            positions.size(), sizeof(positions[0]), target, anywhere);
        if (kept > target + target / 2) {
            std::vector<unsigned int> clustered(finer->size());
            const std::size_t fewer =
                meshopt_simplifySloppy(clustered.data(), finer->data(), finer->size(), positions[0].data(),
                                       positions.size(), sizeof(positions[0]), target, anywhere);
            if (fewer > 0 && fewer < kept) level.swap(clustered), kept = fewer;
        }
        if (kept == 0 || kept >= finer->size()) break;
        level.resize(kept);
        meshopt_optimizeVertexCache(level.data(), level.data(), kept, positions.size());
        levels.push_back(std::move(level));
        finer = &levels.back();
    }
    return levels;
}

// Removes the timings from a run's facts, at any depth ("seconds", "read_seconds", ...): they
// change from run to run, and would change the page's bytes.
void drop_timings(Json& facts) {
    if (!facts.is_object()) return;
    for (auto item = facts.begin(); item != facts.end();) {
        const std::string& key = item.key();
        const bool timing = key == "seconds" || (key.size() > 8 && key.ends_with("_seconds"));
        if (timing)
            item = facts.erase(item);
        else
            drop_timings(*item++);
    }
}

} // namespace

std::string encode_html_mesh(const Mesh& mesh, const HtmlOptions& options) {
    if (mesh.triangles.empty()) throw Error(ErrorKind::output, "the mesh has no triangles, the page cannot show it");
    // Triangles in the order the GPU's vertex cache likes, vertices in the order they are first
    // used (Forsyth's and Kapoulkine's orderings, as meshoptimizer implements them): both make the
    // codecs' deltas small.
    const std::size_t index_count = 3 * mesh.triangles.size();
    std::vector<unsigned int> indices(index_count);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) indices[3 * t + k] = mesh.triangles[t][k];
    meshopt_optimizeVertexCache(indices.data(), indices.data(), index_count, mesh.positions.size());
    std::vector<unsigned int> remap(mesh.positions.size());
    const std::size_t vertices =
        meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), index_count, mesh.positions.size());
    meshopt_remapIndexBuffer(indices.data(), indices.data(), index_count, remap.data());

    const double step = position_step(mesh);
    std::vector<std::array<std::int32_t, 3>> positions(vertices);
    std::vector<std::array<std::uint8_t, 4>> colors(mesh.colors.empty() ? 0 : vertices);
    std::vector<std::array<std::int8_t, 4>> normals(mesh.normals.empty() ? 0 : vertices);
    const bool heat = !options.heat_colors.empty();
    if (heat &&
        (options.heat_colors.size() != mesh.positions.size() || options.heat_distance.size() != mesh.positions.size()))
        throw Error(ErrorKind::output, "the heat map does not have one colour and one distance per vertex");
    std::vector<std::array<std::uint8_t, 4>> heat_colors(heat ? vertices : 0);
    std::vector<float> heat_distance(heat ? vertices : 0);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const unsigned int to = remap[v];
        if (to == ~0u) continue; // used by no triangle
        for (int a = 0; a < 3; ++a)
            positions[to][a] = static_cast<std::int32_t>(std::lround(mesh.positions[v][a] / step));
        if (!colors.empty()) colors[to] = {mesh.colors[v][0], mesh.colors[v][1], mesh.colors[v][2], 255};
        if (heat) {
            const auto& c = options.heat_colors[v];
            heat_colors[to] = {c[0], c[1], c[2], 255};
            heat_distance[to] = static_cast<float>(options.heat_distance[v]);
        }
        if (!normals.empty())
            for (int a = 0; a < 3; ++a)
                normals[to][a] =
                    static_cast<std::int8_t>(std::lround(std::clamp(mesh.normals[v][a], -1.0f, 1.0f) * 127));
    }

    std::string buffers;
    Json layout = Json::object();
    const auto add = [&](const std::string& name, const std::string& bytes) {
        layout[name] = {{"offset", buffers.size()}, {"length", bytes.size()}};
        buffers += bytes;
        buffers.resize((buffers.size() + 3) / 4 * 4, '\0');
    };
    add("positions", encode_vertices(positions));
    if (!colors.empty()) add("colors", encode_vertices(colors));
    if (!normals.empty()) add("normals", encode_vertices(normals));
    if (heat) {
        add("heat_colors", encode_vertices(heat_colors));
        add("heat_distance", encode_vertices(heat_distance));
    }
    std::string encoded_indices(meshopt_encodeIndexBufferBound(index_count, vertices), '\0');
    encoded_indices.resize(meshopt_encodeIndexBuffer(reinterpret_cast<unsigned char*>(encoded_indices.data()),
                                                     encoded_indices.size(), indices.data(), index_count));
    add("indices", encoded_indices);
    std::vector<std::array<float, 3>> at(vertices); // where the simplifier sees the vertices
    for (std::size_t v = 0; v < vertices; ++v)
        for (int a = 0; a < 3; ++a) at[v][a] = static_cast<float>(positions[v][a] * step);
    Json motion = Json::array();
    for (const auto& level : motion_levels(indices, at)) {
        std::string encoded(meshopt_encodeIndexBufferBound(level.size(), vertices), '\0');
        encoded.resize(meshopt_encodeIndexBuffer(reinterpret_cast<unsigned char*>(encoded.data()), encoded.size(),
                                                 level.data(), level.size()));
        const std::string name = "motion_" + std::to_string(motion.size() + 1);
        add(name, encoded);
        motion.push_back({{"buffer", name}, {"triangles", level.size() / 3}});
    }

    Json header = {{"name", utf8_or_latin1(options.name)},
                   {"vertices", vertices},
                   {"triangles", mesh.triangles.size()},
                   {"origin", {mesh.origin[0], mesh.origin[1], mesh.origin[2]}},
                   {"step", step},
                   {"cell_size", mesh.cell_size},
                   {"crs", mesh.crs},
                   {"buffers", layout},
                   {"motion", motion}};
    if (heat) header["heat_scale"] = options.heat_scale;
    Json facts = options.facts_json.empty() ? Json() : Json::parse(options.facts_json);
    if (facts.is_object()) { // what changes from run to run would change the page's bytes
        for (const char* key : {"device", "outputs", "peak_rss_bytes"}) facts.erase(key);
        drop_timings(facts);
    }
    header["facts"] = facts;
    const std::string header_text = json_text(header);
    std::string data = "LMSH";
    data.resize(12 + header_text.size());
    store_le<std::uint32_t>(reinterpret_cast<std::byte*>(data.data() + 4), 1);
    store_le<std::uint32_t>(reinterpret_cast<std::byte*>(data.data() + 8),
                            static_cast<std::uint32_t>(header_text.size()));
    data.replace(12, header_text.size(), header_text);
    data.resize((data.size() + 3) / 4 * 4, ' ');
    return data + buffers;
}

std::string compress_html_mesh(const Mesh& mesh, const HtmlOptions& options) {
    return zlib_compress(encode_html_mesh(mesh, options));
}

namespace {

void check_viewer_built() {
    if (html_viewer_page().empty() || html_viewer_script().empty())
        throw Error(ErrorKind::output, "this lasmesh was built without its HTML viewer (three.js and esbuild from npm "
                                       "were not found when it was built: tools/build.sh installs them)");
}

} // namespace

std::string html_page_with(const std::string& compressed_mesh) {
    check_viewer_built();
    const std::string_view page = html_viewer_page(), script = html_viewer_script();
    const std::string mesh_text = base64(compressed_mesh);
    std::string out(page);
    for (const auto& [mark, text] : {std::pair<std::string_view, std::string_view>{"@LASMESH_VIEWER@", script},
                                     std::pair<std::string_view, std::string_view>{"@LASMESH_MESH@", mesh_text}}) {
        const std::size_t at = out.find(mark);
        if (at == std::string::npos) throw Error(ErrorKind::output, "the HTML page has no place for the viewer");
        out.replace(at, mark.size(), text);
    }
    return out;
}

std::string encode_html(const Mesh& mesh, const HtmlOptions& options) {
    check_viewer_built(); // before the mesh's own checks
    return html_page_with(compress_html_mesh(mesh, options));
}

} // namespace lasmesh
