// SPDX-License-Identifier: Apache-2.0
// read_copc_nodes: the info VLR and the hierarchy pages, as the COPC 1.0 specification lays them out.
#include "read/copc.hpp"

#include "byte_order.hpp"
#include "lasmesh/error.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>

namespace lasmesh {

namespace {

constexpr std::size_t info_size = 160, entry_size = 32;
// A page holds a node and its descendants a few levels down; a million pages would describe
// far more chunks than any file holds points for, so more means the pages point in a loop.
constexpr std::size_t max_pages = 1u << 20;

} // namespace

std::optional<std::vector<CopcNode>> read_copc_nodes(const std::string& path, const LasHeader& header) {
    const Vlr* info = nullptr;
    for (const Vlr& v : header.vlrs)
        if (v.user_id == "copc" && v.record_id == 1) info = &v;
    if (!info) return std::nullopt;
    if (info->data.size() < info_size)
        throw_input_error(path, "its COPC info VLR holds " + std::to_string(info->data.size()) + " bytes, not " +
                                    std::to_string(info_size));
    const std::byte* b = info->data.data();
    const Vec3 centre{load_le<double>(b), load_le<double>(b + 8), load_le<double>(b + 16)};
    const double half = load_le<double>(b + 24);
    const std::uint64_t root_offset = load_le<std::uint64_t>(b + 40), root_size = load_le<std::uint64_t>(b + 48);
    if (!(half > 0) || !std::isfinite(half) || !std::isfinite(centre[0]) || !std::isfinite(centre[1]) ||
        !std::isfinite(centre[2]))
        throw_input_error(path, "its COPC info VLR gives no cube (half size " + std::to_string(half) + ")");

    std::ifstream file(path, std::ios::binary);
    file.seekg(0, std::ios::end);
    const auto size = static_cast<std::uint64_t>(std::max<std::streamoff>(file.tellg(), 0));
    const std::uint64_t data_start = header.offset_to_point_data;

    std::vector<CopcNode> nodes;
    std::vector<std::pair<std::uint64_t, std::uint64_t>> pages{{root_offset, root_size}};
    std::set<std::uint64_t> seen;
    std::vector<std::byte> page;
    while (!pages.empty()) {
        const auto [at, bytes] = pages.back();
        pages.pop_back();
        const std::string where =
            "COPC hierarchy page at byte " + std::to_string(at) + " (" + std::to_string(bytes) + " bytes)";
        if (bytes % entry_size != 0 || at > size || bytes > size - at)
            throw_input_error(path, "its " + where + " is not whole 32-byte entries within the file's " +
                                        std::to_string(size) + " bytes");
        if (!seen.insert(at).second || seen.size() > max_pages)
            throw_input_error(path, "its " + where + " is reached twice: the hierarchy's pages point in a loop");
        page.resize(bytes);
        file.seekg(static_cast<std::streamoff>(at));
        if (!file.read(reinterpret_cast<char*>(page.data()), static_cast<std::streamsize>(bytes)))
            throw_input_error(path, "cannot read its " + where);
        for (std::size_t e = 0; e < bytes; e += entry_size) {
            const std::byte* entry = page.data() + e;
            CopcNode node;
            for (int i = 0; i < 4; ++i) node.key[i] = load_le<std::int32_t>(entry + 4 * i);
            const auto offset = load_le<std::uint64_t>(entry + 16);
            const auto byte_size = load_le<std::int32_t>(entry + 24);
            const auto count = load_le<std::int32_t>(entry + 28);
            if (count == -1) { // another page
                pages.emplace_back(offset, static_cast<std::uint64_t>(std::max(byte_size, 0)));
                continue;
            }
            if (count == 0) continue; // a node without points (its children have some)
            const int level = node.key[0];
            const std::string which = "COPC node " + std::to_string(level) + "-" + std::to_string(node.key[1]) + "-" +
                                      std::to_string(node.key[2]) + "-" + std::to_string(node.key[3]) + " (in the " +
                                      where + ")";
            if (count < 0 || byte_size <= 0 || level < 0 || level > 30 || offset < data_start || offset > size ||
                std::uint64_t(byte_size) > size - offset)
                throw_input_error(path, which + " has " + std::to_string(count) + " points in " +
                                            std::to_string(byte_size) + " bytes at byte " + std::to_string(offset) +
                                            ", outside the point data (bytes " + std::to_string(data_start) + " to " +
                                            std::to_string(size) + ")");
            node.offset = offset;
            node.bytes = static_cast<std::uint64_t>(byte_size);
            node.points = static_cast<std::uint64_t>(count);
            const double edge = 2 * half / std::ldexp(1.0, level);
            for (int a = 0; a < 3; ++a) {
                node.cube.min[a] = centre[a] - half + edge * node.key[1 + a];
                node.cube.max[a] = node.cube.min[a] + edge;
            }
            nodes.push_back(node);
        }
    }
    std::sort(nodes.begin(), nodes.end(), [](const CopcNode& a, const CopcNode& b) { return a.offset < b.offset; });
    std::uint64_t points = 0;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        if (i > 0 && nodes[i - 1].offset + nodes[i - 1].bytes > nodes[i].offset)
            throw_input_error(path, "its COPC nodes at bytes " + std::to_string(nodes[i - 1].offset) + " and " +
                                        std::to_string(nodes[i].offset) + " overlap");
        points += nodes[i].points;
    }
    if (points != header.point_count)
        throw_input_error(path, "its COPC hierarchy's nodes hold " + std::to_string(points) +
                                    " points, but the header counts " + std::to_string(header.point_count));
    return nodes;
}

} // namespace lasmesh
