// SPDX-License-Identifier: Apache-2.0
// render_preview: four orthographic views of a mesh, rasterised with edge functions and a depth
// buffer (the classic scan conversion: Pineda 1988, "A parallel algorithm for polygon
// rasterization"), Gouraud-shaded; encode_png through libpng's simplified API.
#include "io/png_preview.hpp"

#include "lasmesh/error.hpp"

#include <png.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace lasmesh {

// Named, not anonymous: a unity build puts this file beside others with their own vector helpers.
namespace preview {

using V3 = std::array<double, 3>;

V3 cross(const V3& a, const V3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V3& a, const V3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
V3 normalized(const V3& v) {
    const double length = std::sqrt(dot(v, v));
    return length > 0 ? V3{v[0] / length, v[1] / length, v[2] / length} : V3{0, 0, 1};
}

// A camera looking along `forward` (LAS axes, z up): screen x along `right`, y along `up`.
struct View {
    V3 right, up, forward;
};

View looking(const V3& direction) {
    const V3 forward = normalized(direction);
    V3 right = cross(forward, {0, 0, 1});
    right = dot(right, right) < 1e-12 ? V3{1, 0, 0} : normalized(right); // straight down: x to the right
    return {right, cross(right, forward), forward};
}

// Per-vertex normals: the mesh's own, else the area-weighted sum of the faces around each vertex.
std::vector<V3> vertex_normals(const Mesh& mesh) {
    std::vector<V3> normals(mesh.positions.size(), V3{0, 0, 0});
    if (mesh.normals.size() == mesh.positions.size()) {
        for (std::size_t v = 0; v < normals.size(); ++v)
            normals[v] = {mesh.normals[v][0], mesh.normals[v][1], mesh.normals[v][2]};
        return normals;
    }
    for (const auto& t : mesh.triangles) {
        const auto& a = mesh.positions[t[0]];
        const auto& b = mesh.positions[t[1]];
        const auto& c = mesh.positions[t[2]];
        const V3 n = cross({double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]},
                           {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]});
        for (const std::uint32_t v : t)
            for (int k = 0; k < 3; ++k) normals[v][k] += n[k];
    }
    for (V3& n : normals) n = normalized(n);
    return normals;
}

// One panel of `image`: the mesh seen through `view`, fitted into x0..x0+w, y0..y0+h.
void render_panel(const Mesh& mesh, const std::vector<V3>& normals, const View& view, PreviewImage& image, int x0,
                  int y0, int w, int h) {
    const std::size_t n = mesh.positions.size();
    std::vector<std::array<float, 3>> screen(n); // x, y in pixels, depth
    std::vector<std::array<float, 3>> shade(n);  // the lit colour, 0-255
    double lo[2] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
    double hi[2] = {std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest()};
    for (const auto& p : mesh.positions) {
        const V3 q{p[0], p[1], p[2]};
        const double s[2] = {dot(q, view.right), dot(q, view.up)};
        for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], s[k]), hi[k] = std::max(hi[k], s[k]);
    }
    const double margin = 0.05 * std::min(w, h);
    const double span_x = std::max(hi[0] - lo[0], 1e-9), span_y = std::max(hi[1] - lo[1], 1e-9);
    const double scale = std::min((w - 2 * margin) / span_x, (h - 2 * margin) / span_y);
    const double cx = 0.5 * (lo[0] + hi[0]), cy = 0.5 * (lo[1] + hi[1]);
    // Over the viewer's left shoulder, from above; both faces lit alike.
    const V3 light = normalized({-view.forward[0] + 0.5 * view.up[0] - 0.35 * view.right[0],
                                 -view.forward[1] + 0.5 * view.up[1] - 0.35 * view.right[1],
                                 -view.forward[2] + 0.5 * view.up[2] - 0.35 * view.right[2]});
    const bool colored = mesh.colors.size() == n;
    for (std::size_t v = 0; v < n; ++v) {
        const V3 q{mesh.positions[v][0], mesh.positions[v][1], mesh.positions[v][2]};
        screen[v] = {static_cast<float>(x0 + 0.5 * w + (dot(q, view.right) - cx) * scale),
                     static_cast<float>(y0 + 0.5 * h - (dot(q, view.up) - cy) * scale),
                     static_cast<float>(dot(q, view.forward))};
        const double intensity = 0.3 + 0.7 * std::abs(dot(normals[v], light));
        for (int k = 0; k < 3; ++k) shade[v][k] = static_cast<float>((colored ? mesh.colors[v][k] : 190) * intensity);
    }
    std::vector<float> depth(std::size_t(w) * h, std::numeric_limits<float>::infinity());
    for (const auto& t : mesh.triangles) {
        const auto& a = screen[t[0]];
        const auto& b = screen[t[1]];
        const auto& c = screen[t[2]];
        const float area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if (!(std::abs(area) > 1e-12f)) continue; // seen edge-on
        const int left = std::max(x0, static_cast<int>(std::floor(std::min({a[0], b[0], c[0]}))));
        const int right = std::min(x0 + w - 1, static_cast<int>(std::ceil(std::max({a[0], b[0], c[0]}))));
        const int top = std::max(y0, static_cast<int>(std::floor(std::min({a[1], b[1], c[1]}))));
        const int bottom = std::min(y0 + h - 1, static_cast<int>(std::ceil(std::max({a[1], b[1], c[1]}))));
        for (int y = top; y <= bottom; ++y)
            for (int x = left; x <= right; ++x) {
                const float px = x + 0.5f, py = y + 0.5f;
                // Barycentric weights from the edge functions, whatever the winding.
                const float wa = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
                const float wb = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
                const float wc = 1 - wa - wb;
                if (wa < 0 || wb < 0 || wc < 0) continue;
                const float z = wa * a[2] + wb * b[2] + wc * c[2];
                float& nearest = depth[std::size_t(y - y0) * w + (x - x0)];
                if (!(z < nearest)) continue;
                nearest = z;
                std::uint8_t* out = &image.rgb[(std::size_t(y) * image.width + x) * 3];
                for (int k = 0; k < 3; ++k) {
                    const float value = wa * shade[t[0]][k] + wb * shade[t[1]][k] + wc * shade[t[2]][k];
                    out[k] = static_cast<std::uint8_t>(std::clamp(value + 0.5f, 0.0f, 255.0f));
                }
            }
    }
}

} // namespace preview

PreviewImage render_preview(const Mesh& mesh, int width, int height) {
    PreviewImage image;
    image.width = width;
    image.height = height;
    image.rgb.assign(std::size_t(width) * height * 3, 255); // white
    const int w = width / 2, h = height / 2;
    // A grey line between the panels.
    for (int y = 0; y < height; ++y)
        for (int x = w - 1; x <= w; ++x) std::fill_n(&image.rgb[(std::size_t(y) * width + x) * 3], 3, 200);
    for (int y = h - 1; y <= h; ++y) std::fill_n(&image.rgb[std::size_t(y) * width * 3], std::size_t(width) * 3, 200);
    if (mesh.triangles.empty()) return image;
    using namespace preview;
    const std::vector<V3> normals = vertex_normals(mesh);
    const double c30 = std::cos(M_PI / 6), s30 = std::sin(M_PI / 6);
    const std::array<View, 4> views{looking({0, 0, -1}), looking({0, 1, 0}), looking({-1, 0, 0}),
                                    looking({c30 * M_SQRT1_2, c30 * M_SQRT1_2, -s30})};
    // Each panel its own pixels: the same image for any thread count.
    tbb::parallel_for(0, 4, [&](int p) {
        render_panel(mesh, normals, views[p], image, (p % 2) * w + 1, (p / 2) * h + 1, w - 2, h - 2);
    });
    return image;
}

std::string encode_png(const PreviewImage& image) {
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    png.width = static_cast<png_uint_32>(image.width);
    png.height = static_cast<png_uint_32>(image.height);
    png.format = PNG_FORMAT_RGB;
    png_alloc_size_t size = 0;
    if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.rgb.data(), 0, nullptr))
        throw Error(ErrorKind::output, std::string("PNG encoding failed: ") + png.message);
    std::string bytes(size, '\0');
    if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, image.rgb.data(), 0, nullptr))
        throw Error(ErrorKind::output, std::string("PNG encoding failed: ") + png.message);
    bytes.resize(size);
    return bytes;
}

} // namespace lasmesh
