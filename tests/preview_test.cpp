// SPDX-License-Identifier: Apache-2.0
// The preview picture: what each panel shows, the depth test, and the PNG that holds it.
#include "io/png_preview.hpp"

#include <doctest/doctest.h>
#include <png.h>
#include <tbb/global_control.h>

#include <array>
#include <cstring>
#include <utility>

using namespace lasmesh;

namespace {

// A rectangle x in [0, 10], y in [0, 5] at height z, in one colour, as two triangles.
void add_rectangle(Mesh& mesh, float z, std::array<std::uint8_t, 3> color) {
    const auto first = static_cast<std::uint32_t>(mesh.positions.size());
    for (const auto& p : {std::array<float, 3>{0, 0, z}, {10, 0, z}, {10, 5, z}, {0, 5, z}}) {
        mesh.positions.push_back(p);
        mesh.colors.push_back(color);
    }
    mesh.triangles.push_back({first, first + 1, first + 2});
    mesh.triangles.push_back({first, first + 2, first + 3});
}

std::array<int, 3> pixel(const PreviewImage& image, int x, int y) {
    const std::uint8_t* p = &image.rgb[(std::size_t(y) * image.width + x) * 3];
    return {p[0], p[1], p[2]};
}

} // namespace

TEST_CASE("preview: the top panel shows the surface in its colour, lit; edge-on panels and margins stay white") {
    Mesh mesh;
    add_rectangle(mesh, 0, {220, 30, 30});
    const PreviewImage image = render_preview(mesh, 400, 300);
    REQUIRE(image.rgb.size() == 400u * 300 * 3);
    // Top panel (top left, 200 x 150): its centre is the rectangle, red and lit (at least 30%).
    const auto centre = pixel(image, 100, 75);
    CHECK(centre[0] > 150); // facing the light: nearly fully lit
    CHECK(centre[0] > 3 * centre[1]);
    CHECK(centre[1] == centre[2]);
    CHECK(pixel(image, 5, 5) == std::array<int, 3>{255, 255, 255}); // the margin
    // The rectangle fills the panel's width less its margins: a 2:1 rectangle in a 4:3 panel.
    int covered = 0;
    for (int x = 0; x < 200; ++x) covered += pixel(image, x, 75) != std::array<int, 3>{255, 255, 255};
    CHECK(covered > 150);
    CHECK(covered < 190);
    // The front panel (top right) sees the flat rectangle edge-on: nothing to draw.
    CHECK(pixel(image, 300, 75) == std::array<int, 3>{255, 255, 255});
    // Sheets are seen from both sides: the other winding (normals down) looks the same from above.
    Mesh flipped = mesh;
    for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
    CHECK(render_preview(flipped, 400, 300).rgb == image.rgb);
}

TEST_CASE("preview: the depth test keeps the surface nearest the viewer, whatever the drawing order") {
    for (const bool blue_first : {false, true}) {
        Mesh mesh;
        if (blue_first) add_rectangle(mesh, 1, {30, 30, 220});
        add_rectangle(mesh, 0, {220, 30, 30});
        if (!blue_first) add_rectangle(mesh, 1, {30, 30, 220});
        const PreviewImage image = render_preview(mesh, 400, 300);
        const auto top = pixel(image, 100, 75); // looking down: z = 1 is nearer
        CAPTURE(blue_first);
        CHECK(top[2] > 3 * top[0]);
    }
}

TEST_CASE("preview: the same pixels with one thread or many; PNG holds them exactly") {
    Mesh mesh;
    add_rectangle(mesh, 0, {200, 180, 40});
    add_rectangle(mesh, 2, {40, 180, 200});
    mesh.positions[5][2] = 4; // a slope, so every view sees something
    const PreviewImage many = render_preview(mesh, 320, 240);
    PreviewImage one;
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        one = render_preview(mesh, 320, 240);
    }
    CHECK(one.rgb == many.rgb);
    const std::string png = encode_png(many);
    REQUIRE(png.size() > 8);
    CHECK(std::memcmp(png.data(), "\x89PNG\r\n\x1a\n", 8) == 0);
    png_image read{};
    read.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_memory(&read, png.data(), png.size()));
    read.format = PNG_FORMAT_RGB;
    CHECK(read.width == 320);
    CHECK(read.height == 240);
    std::vector<std::uint8_t> pixels(PNG_IMAGE_SIZE(read));
    REQUIRE(png_image_finish_read(&read, nullptr, pixels.data(), 0, nullptr));
    CHECK(pixels == many.rgb);
}
