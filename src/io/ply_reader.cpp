// SPDX-License-Identifier: Apache-2.0
// PLY reader: the header describes elements as lists of typed properties; the body is read
// element by element, keeping only what a mesh needs.
#include "io/ply_reader.hpp"

#include "lasmesh/error.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace lasmesh {

namespace {

enum class Type { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

struct Property {
    std::string name;
    Type type = Type::float32;
    bool is_list = false;
    Type count_type = Type::uint8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
};

enum class Format { ascii, little_endian, big_endian };

bool parse_type(const std::string& text, Type& type) {
    static const std::pair<const char*, Type> names[] = {
        {"char", Type::int8},     {"int8", Type::int8},       {"uchar", Type::uint8},    {"uint8", Type::uint8},
        {"short", Type::int16},   {"int16", Type::int16},     {"ushort", Type::uint16},  {"uint16", Type::uint16},
        {"int", Type::int32},     {"int32", Type::int32},     {"uint", Type::uint32},    {"uint32", Type::uint32},
        {"float", Type::float32}, {"float32", Type::float32}, {"double", Type::float64}, {"float64", Type::float64}};
    for (const auto& [name, t] : names)
        if (text == name) return type = t, true;
    return false;
}

std::size_t type_size(Type t) {
    switch (t) {
    case Type::int8:
    case Type::uint8: return 1;
    case Type::int16:
    case Type::uint16: return 2;
    case Type::int32:
    case Type::uint32:
    case Type::float32: return 4;
    case Type::float64: return 8;
    }
    return 0;
}

// The body as a cursor that reads one value of any type, in the file's encoding.
class Body {
  public:
    Body(const std::string& path, std::vector<char> bytes, std::size_t offset, Format format)
        : path_(path), bytes_(std::move(bytes)), at_(offset), format_(format) {}

    double value(Type type, const std::string& what) {
        return format_ == Format::ascii ? ascii_value(what) : binary_value(type, what);
    }
    std::size_t offset() const { return at_; }
    [[noreturn]] void fail(const std::string& what) const {
        throw Error(ErrorKind::input, path_ + ": byte " + std::to_string(at_) + ": " + what);
    }

  private:
    double ascii_value(const std::string& what) {
        while (at_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[at_]))) ++at_;
        double v = 0;
        const auto [end, ec] = std::from_chars(bytes_.data() + at_, bytes_.data() + bytes_.size(), v);
        if (ec != std::errc{})
            fail("expected a number for " + what + (at_ >= bytes_.size() ? ", found the end of the file" : ""));
        at_ = static_cast<std::size_t>(end - bytes_.data());
        return v;
    }
    double binary_value(Type type, const std::string& what) {
        const std::size_t n = type_size(type);
        if (bytes_.size() - at_ < n)
            fail("the file ends inside " + what + " (" + std::to_string(bytes_.size()) + " bytes in all)");
        unsigned char b[8];
        std::memcpy(b, bytes_.data() + at_, n);
        if ((format_ == Format::big_endian) == (std::endian::native == std::endian::little))
            for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
        at_ += n;
        switch (type) {
        case Type::int8: return static_cast<std::int8_t>(b[0]);
        case Type::uint8: return b[0];
        case Type::int16: {
            std::int16_t v;
            std::memcpy(&v, b, 2);
            return v;
        }
        case Type::uint16: {
            std::uint16_t v;
            std::memcpy(&v, b, 2);
            return v;
        }
        case Type::int32: {
            std::int32_t v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Type::uint32: {
            std::uint32_t v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Type::float32: {
            float v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Type::float64: {
            double v;
            std::memcpy(&v, b, 8);
            return v;
        }
        }
        return 0;
    }

    std::string path_;
    std::vector<char> bytes_;
    std::size_t at_;
    Format format_;
};

std::uint8_t to_8bit(double v, Type type) {
    if (type == Type::float32 || type == Type::float64)
        v *= 255; // colours as 0..1
    else if (type == Type::uint16 || type == Type::int16)
        v /= 257;
    return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

} // namespace

Mesh read_ply(const std::string& path) {
    if (std::filesystem::is_directory(path))
        throw Error(ErrorKind::input, path + ": is a directory, expected a mesh file");
    std::ifstream file(path, std::ios::binary);
    if (!file) throw Error(ErrorKind::input, path + ": cannot open the mesh file");
    std::vector<char> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());

    // Header: text lines up to "end_header".
    Mesh mesh;
    std::vector<Element> elements;
    Format format = Format::ascii;
    std::size_t at = 0;
    bool have_format = false;
    for (int line_number = 1;; ++line_number) {
        const std::size_t start = at;
        while (at < bytes.size() && bytes[at] != '\n') ++at;
        if (at >= bytes.size())
            throw Error(ErrorKind::input,
                        path + ": byte " + std::to_string(start) + ": the PLY header has no end_header line");
        std::string line(bytes.data() + start, bytes.data() + at++);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        auto bad = [&](const std::string& what) {
            return Error(ErrorKind::input, path + ": header line " + std::to_string(line_number) + " (byte " +
                                               std::to_string(start) + "): " + what + ", found \"" + line + "\"");
        };
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (line_number == 1) {
            if (line != "ply") throw bad("not a PLY file: expected \"ply\" on the first line");
            continue;
        }
        if (keyword == "end_header") break;
        if (keyword == "format") {
            std::string name, version;
            words >> name >> version;
            if (name == "ascii")
                format = Format::ascii;
            else if (name == "binary_little_endian")
                format = Format::little_endian;
            else if (name == "binary_big_endian")
                format = Format::big_endian;
            else
                throw bad("expected format ascii, binary_little_endian or binary_big_endian");
            have_format = true;
        } else if (keyword == "element") {
            Element e;
            if (!(words >> e.name >> e.count)) throw bad("expected \"element NAME COUNT\"");
            elements.push_back(e);
        } else if (keyword == "property") {
            if (elements.empty()) throw bad("a property before any element");
            Property p;
            std::string first;
            words >> first;
            if (first == "list") {
                std::string count_type, item_type;
                words >> count_type >> item_type >> p.name;
                p.is_list = true;
                if (!parse_type(count_type, p.count_type) || !parse_type(item_type, p.type) || p.name.empty())
                    throw bad("expected \"property list COUNT_TYPE ITEM_TYPE NAME\"");
            } else if (!parse_type(first, p.type) || !(words >> p.name)) {
                throw bad("expected \"property TYPE NAME\" with a PLY type");
            }
            elements.back().properties.push_back(p);
        } else if (keyword == "comment") {
            std::string what;
            words >> what;
            // Every distance is measured from these: a value that does not parse must not become 0.
            auto finite = [&](double& v) {
                std::string text;
                words >> text;
                const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
                return !text.empty() && ec == std::errc() && end == text.data() + text.size() && std::isfinite(v);
            };
            if (what == "origin" && !(finite(mesh.origin[0]) && finite(mesh.origin[1]) && finite(mesh.origin[2])))
                throw bad("expected \"comment origin X Y Z\" with three finite numbers");
            if (what == "cell_size" && !(finite(mesh.cell_size) && mesh.cell_size >= 0))
                throw bad("expected \"comment cell_size C\" with a finite number >= 0");
            if (what == "crs") {
                std::getline(words >> std::ws, mesh.crs);
                if (!mesh.crs.empty() && mesh.crs.back() == '\r') mesh.crs.pop_back();
            }
        } else if (keyword != "obj_info" && !keyword.empty()) {
            throw bad("unknown header keyword");
        }
    }
    if (!have_format) throw Error(ErrorKind::input, path + ": the PLY header has no format line");

    // The counts are checked against the file's size before anything is allocated for them: a
    // 177-byte file may declare 2^32 - 1 vertices. Every record takes at least one byte, which
    // bounds the allocation by the file's size; the exact shortfall is found while reading.
    {
        std::uint64_t least = 0;
        for (const Element& e : elements)
            if (!e.properties.empty() && __builtin_add_overflow(least, e.count, &least)) least = UINT64_MAX;
        if (least > bytes.size() - at)
            throw Error(ErrorKind::input, path + ": byte " + std::to_string(at) +
                                              ": the PLY header declares elements that need at least " +
                                              std::to_string(least) + " bytes, but only " +
                                              std::to_string(bytes.size() - at) +
                                              " follow it (truncated or damaged file)");
    }
    Body body(path, std::move(bytes), at, format);
    bool have_vertices = false;
    for (const Element& e : elements) {
        const bool vertex = e.name == "vertex", face = e.name == "face";
        static const char* const xyz_names[] = {"x", "y", "z"};
        static const char* const rgb_names[] = {"red", "green", "blue"};
        static const char* const normal_names[] = {"nx", "ny", "nz"};
        int xyz[3] = {-1, -1, -1}, rgb[3] = {-1, -1, -1}, nxyz[3] = {-1, -1, -1}, indices = -1;
        for (int i = 0; i < static_cast<int>(e.properties.size()); ++i) {
            const std::string& n = e.properties[i].name;
            for (int a = 0; a < 3; ++a) {
                if (n == xyz_names[a]) xyz[a] = i;
                if (n == rgb_names[a]) rgb[a] = i;
                if (n == normal_names[a]) nxyz[a] = i;
            }
            if (n == "vertex_indices" || n == "vertex_index") indices = i;
        }
        if (vertex) {
            if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) body.fail("the vertex element has no x, y, z properties");
            have_vertices = true;
            if (e.count > (1ull << 32) - 1) body.fail("more than 2^32 - 1 vertices");
            mesh.positions.resize(e.count);
            if (rgb[0] >= 0 && rgb[1] >= 0 && rgb[2] >= 0) mesh.colors.resize(e.count);
            if (nxyz[0] >= 0 && nxyz[1] >= 0 && nxyz[2] >= 0) mesh.normals.resize(e.count);
        }
        if (face && indices < 0) body.fail("the face element has no vertex_indices list");
        std::vector<std::uint32_t> polygon;
        for (std::uint64_t r = 0; r < e.count; ++r) {
            for (int i = 0; i < static_cast<int>(e.properties.size()); ++i) {
                const Property& p = e.properties[i];
                const std::string what = e.name + " " + std::to_string(r) + " property " + p.name;
                if (!p.is_list) {
                    const double v = body.value(p.type, what);
                    if (vertex)
                        for (int a = 0; a < 3; ++a) {
                            if (i == xyz[a]) mesh.positions[r][a] = static_cast<float>(v);
                            if (i == rgb[a] && !mesh.colors.empty()) mesh.colors[r][a] = to_8bit(v, p.type);
                            if (i == nxyz[a] && !mesh.normals.empty()) mesh.normals[r][a] = static_cast<float>(v);
                        }
                    continue;
                }
                const double count = body.value(p.count_type, what + " (list length)");
                if (count < 0 || count != std::floor(count) || count > 1e6) body.fail("bad list length for " + what);
                polygon.clear();
                for (std::uint64_t k = 0; k < static_cast<std::uint64_t>(count); ++k) {
                    const double index = body.value(p.type, what);
                    if (face && i == indices) {
                        if (!(index >= 0 && index < static_cast<double>(mesh.positions.size())))
                            body.fail(what + ": vertex index " + std::to_string(static_cast<long long>(index)) +
                                      " is not below the vertex count " + std::to_string(mesh.positions.size()));
                        polygon.push_back(static_cast<std::uint32_t>(index));
                    }
                }
                for (std::size_t k = 2; k < polygon.size(); ++k) // a fan; a triangle stays as it is
                    mesh.triangles.push_back({polygon[0], polygon[k - 1], polygon[k]});
            }
        }
    }
    if (!have_vertices) body.fail("the PLY file has no vertex element");
    for (const auto& p : mesh.positions)
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            body.fail("a vertex position is not a finite number");
    return mesh;
}

} // namespace lasmesh
