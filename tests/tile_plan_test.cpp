// SPDX-License-Identifier: Apache-2.0
// A survey over many machines as library calls: plan_tiles, run_tile for each tile, merge_tiles
// give the bytes build_mesh gives; a tile's file read back whole, and every kind of damage told.
#include "lasmesh/build_mesh.hpp"
#include "lasmesh/error.hpp"

#include "build_steps.hpp"
#include "grid/tile_cells.hpp"
#include "mesh/tiled_sheet.hpp"

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>

using namespace lasmesh;

namespace {

using test::contains;
using test::error_text;

// The generated torus, `points` of it, as a LAS file in `dir`; its path.
std::string torus_file(const test::TempDir& dir, std::uint64_t points) {
    lasgen::SceneOptions scene;
    scene.kind = lasgen::SceneKind::torus;
    const std::string input = dir.file("torus.las");
    test::write_file(input, test::make_las(lasgen::LasLayout{}, lasgen::make_scene(scene), points, 4));
    return input;
}

OutputRequest request(const std::string& path) {
    OutputRequest output;
    output.path = path;
    return output;
}

} // namespace

TEST_CASE("a tile's cell sums: read back exactly; cut short, damaged or not a tile's: a clear error") {
    test::TempDir dir;
    TileCells tile;
    tile.plan_hash = 0x1234567890abcdefULL, tile.index = 3, tile.color = true, tile.color_max_word = 255;
    tile.device = "a device";
    tile.inputs = {{0, 100, 2}, {4, 50, 0}};
    tile.warnings = {{4, "warning: x"}};
    tile.brick_keys = {5, 9}, tile.brick_masks = {0b101, 0b1}, tile.brick_first = {0, 2};
    tile.cells = {{3, {1, 2, 3}, {4, 5, 6}}, {7, {8, 9, 10}, {11, 12, 13}}, {14, {15, 16, 17}, {18, 19, 20}}};
    const std::string path = dir.file("t.cells");
    write_tile_cells(tile, path);
    const TileCells back = read_tile_cells(path);
    CHECK(back.plan_hash == tile.plan_hash);
    CHECK(back.index == 3);
    CHECK(back.color);
    CHECK(back.color_max_word == 255);
    CHECK(back.device == "a device");
    REQUIRE(back.inputs.size() == 2);
    CHECK(back.inputs[1].input == 4);
    CHECK(back.inputs[0].outside == 2);
    REQUIRE(back.warnings.size() == 1);
    CHECK(back.warnings[0].text == "warning: x");
    CHECK(back.brick_keys == tile.brick_keys);
    CHECK(back.brick_masks == tile.brick_masks);
    REQUIRE(back.cells.size() == 3);
    CHECK(back.cells[2].count == 14);
    CHECK(back.cells[1].position[2] == 10);
    CHECK(back.cells[2].color[2] == 20);

    const test::Bytes bytes = test::read_file(path);
    test::Bytes cut(bytes.begin(), bytes.end() - 30);
    test::write_file(path, cut);
    CHECK(contains(error_text([&] { read_tile_cells(path); }), "cut short"));
    test::Bytes flipped = bytes; // the last cell's blue sum: a number like any other, but the hash differs
    flipped[bytes.size() - 16] ^= std::byte{1};
    test::write_file(path, flipped);
    CHECK(contains(error_text([&] { read_tile_cells(path); }), "damaged: its hash does not match"));
    test::Bytes other = bytes;
    other[0] = std::byte{'X'};
    test::write_file(path, other);
    CHECK(contains(error_text([&] { read_tile_cells(path); }), "not a lasmesh tile's cell sums"));
    CHECK(contains(error_text([&] { read_tile_cells(dir.file("none.cells")); }), "missing"));
}

TEST_CASE("plan_tiles, run_tile and merge_tiles: the outputs of build_mesh, byte for byte") {
    test::TempDir dir;
    const std::string input = torus_file(dir, 80000);
    BuildOptions options;
    options.grid = GridRequest::longest(96);
    options.outputs.push_back(request(dir.file("one.ply")));
    build_mesh(input, options);

    TilePlan plan = plan_tiles({input}, options, 2.5);
    CHECK(plan.tile_cells % 4 == 0);
    REQUIRE(plan.tiles.size() >= 9);
    write_plan(plan, dir.file("torus.plan.json"));
    const TilePlan read = read_plan(dir.file("torus.plan.json"));
    CHECK(read.hash == plan.hash);
    CHECK(read.grid.cell_size == plan.grid.cell_size);
    BuildOptions merged = options;
    merged.outputs = {request(dir.file("merged.ply"))};
    // Not all tiles yet: every missing one named, nothing written.
    run_tile(read, 0, options);
    const std::string missing = error_text([&] { merge_tiles(read, merged); });
    CHECK(contains(missing, std::to_string(read.tiles.size() - 1) + " of " + std::to_string(read.tiles.size()) +
                                " tiles missing or damaged: 1-" + std::to_string(read.tiles.size() - 1)));
    CHECK(!std::filesystem::exists(dir.file("merged.ply")));
    std::uint64_t in_tiles = 0;
    for (std::size_t k = 0; k < read.tiles.size(); ++k) in_tiles += run_tile(read, k, options).points_in_tile;
    CHECK(in_tiles == 80000); // every point in exactly one tile
    const BuildResult result = merge_tiles(read, merged);
    CHECK(result.report.points_read == 80000);
    CHECK(test::read_file(dir.file("merged.ply")) == test::read_file(dir.file("one.ply")));
    // A tile that counts points another tile counted (a whole, valid file): merge refuses.
    TileCells counted_twice = read_tile_cells(tile_path(read, 1));
    counted_twice.inputs.front().records += 5;
    write_tile_cells(counted_twice, tile_path(read, 1));
    merged.outputs = {request(dir.file("twice.ply"))};
    CHECK(contains(error_text([&] { merge_tiles(read, merged); }), "the tiles counted 80005 of its 80000 points"));
    CHECK(!std::filesystem::exists(dir.file("twice.ply")));
    CHECK(contains(error_text([&] { run_tile(read, read.tiles.size(), options); }), "its tiles are 0 to"));
    BuildOptions scanned = options;
    scanned.scan_bounds = true;
    CHECK(contains(error_text([&] { plan_tiles({input}, scanned, 2.5); }), "a plan reads headers only"));
    merged.tile_size = read.tile_size / 2; // the plan fixes a tileset's tiles
    CHECK(contains(error_text([&] { merge_tiles(read, merged); }), "the plan fixes the tiles' size"));
}

TEST_CASE("a tile's part with a halo, read from the tiles' files, is the whole grid's cells there") {
    // The torus in tiles of 2.5 (24 cells); each tile's window with halos of 8 and 30 cells (past
    // its neighbours into the next), and a window of the grid's last cells beyond every tile.
    test::TempDir dir;
    const std::string input = torus_file(dir, 60000);
    BuildOptions options;
    options.grid = GridRequest::longest(96);
    TilePlan plan = plan_tiles({input}, options, 2.5);
    REQUIRE(plan.tiles.size() >= 9);
    write_plan(plan, dir.file("torus.plan.json"));
    for (std::size_t k = 0; k < plan.tiles.size(); ++k) run_tile(plan, k, options);
    AccumulateOptions whole_grid;
    whole_grid.spec = plan.grid;
    const CellGrid whole = test::accumulate_file(input, whole_grid);
    REQUIRE(whole.occupied_cells() > 1000);
    std::vector<std::array<std::int64_t, 4>> windows = tile_windows(plan.grid, plan.tile_cells);
    const auto d = [&](int a) { return std::int64_t{plan.grid.dims[a]}; };
    windows.push_back({d(0) - 4, d(0), d(1) - 4, d(1)});
    std::size_t compared = 0;
    for (const auto& w : windows)
        for (const std::int64_t halo : {8, 30}) {
            CAPTURE(w[0]);
            CAPTURE(w[2]);
            CAPTURE(halo);
            const CellGrid got = planned_part(plan, w, halo, whole);
            const CellGrid expected = bricks_within(whole, w[0] - halo, w[1] + halo, w[2] - halo, w[3] + halo);
            CHECK(got.brick_keys == expected.brick_keys);
            CHECK(got.brick_masks == expected.brick_masks);
            CHECK(got.brick_first == expected.brick_first);
            REQUIRE(got.cells.size() == expected.cells.size());
            std::size_t differing = 0;
            for (std::size_t c = 0; c < got.cells.size(); ++c) {
                const CellSums &a = got.cells[c], &b = expected.cells[c];
                differing +=
                    a.count != b.count || a.position != b.position || a.color != b.color || a.moments != b.moments;
            }
            CHECK(differing == 0);
            CHECK(got.find(0, 0, 0) == nullptr); // indexed: a cell of the part is found, one outside is not
            if (!got.cells.empty()) {
                const auto at =
                    got.cell_in_brick(got.brick_keys.front(), unsigned(std::countr_zero(got.brick_masks.front())));
                CHECK(got.find(at[0], at[1], at[2]) == &got.cells.front());
            }
            compared += got.cells.size();
        }
    CHECK(compared > 2 * whole.occupied_cells());
}

TEST_CASE("a tile's cells: whole bricks; a plan's tiles rounded again to a coarser grid give that grid's tiles") {
    CHECK(tile_cells_for(12, 0.1663) == 76); // 72.2 cells, then whole bricks
    CHECK(tile_cells_for(1e-6, 1) == 4);
    CHECK(tile_cells_for(1e9, 1) == max_grid_cells);
    for (const double cell : {0.1, 0.1663, 0.0626348, 1.0 / 3, 137.25})
        for (std::uint32_t cells = 4; cells <= 1024; cells += 4) {
            CHECK(tile_cells_for(double(cells) * cell, cell) == cells); // a product's last bit is not a cell more
            const double size = double(cells) * cell * 0.937;           // a user's size, between bricks
            const double planned = double(tile_cells_for(size, cell)) * cell;
            for (int coarser = 1; coarser <= 3; ++coarser) {
                const double cell2 = std::ldexp(cell, coarser); // the automatic grid coarsened after reading
                CHECK(tile_cells_for(planned, cell2) == tile_cells_for(size, cell2));
            }
        }
}

TEST_CASE("a tile job's brick index covers its tile, not the survey: a wide survey's tile runs in memory for its own "
          "cells") {
    // Two small clusters 40 m apart at 1 cm cells: the plan's grid is 4,001 x 4,001 x 201 cells,
    // whose brick index alone takes 204 MB; a tile of 10 m, 13 MB.
    test::TempDir dir;
    std::vector<lasgen::GeneratedPoint> points;
    for (int i = 0; i < 2000; ++i) {
        const double u = 0.001 * (i % 50), v = 0.001 * (i / 50);
        points.push_back({{1 + u, 1 + v, 1}, {200, 100, 50}, 1});
        points.push_back({{39 + u, 39 + v, 1.5}, {50, 100, 200}, 1});
    }
    const std::string input = dir.file("wide.las");
    test::write_file(input, test::las_with_points(points, {0, 0, 0}, {40, 40, 2}));
    BuildOptions options;
    options.grid = GridRequest::cell_edge(0.01);
    TilePlan plan = plan_tiles({input}, options, 10);
    write_plan(plan, dir.file("wide.plan.json"));
    REQUIRE(plan.grid.dims[0] == 4001);
    REQUIRE(plan.tiles.size() == 25);
    const std::uint64_t survey_index = (4004 / 4) * (4004 / 4) * (204 / 4) * 4;
    CHECK(survey_index > 200'000'000);
    // Room for the tile's index and slices, not for the survey's index (the device and its
    // runtime made first, by a tile run without a limit, so that they are counted in use).
    run_tile(plan, 1, options);
    BuildOptions tight = options;
    tight.max_memory = resident_bytes() + 100'000'000;
    const TileReport first = run_tile(plan, 0, tight);
    CHECK(first.points_in_tile == 2000);
    std::size_t far = 0; // the tile of the cluster at 39 m: cell 3,900 or so
    for (std::size_t k = 0; k < plan.tiles.size(); ++k)
        if (plan.tiles[k].x_cells[0] <= 3900 && plan.tiles[k].x_cells[1] > 3900 && plan.tiles[k].y_cells[0] <= 3900 &&
            plan.tiles[k].y_cells[1] > 3900)
            far = k;
    REQUIRE(far > 0);
    const TileReport last = run_tile(plan, far, tight);
    CHECK(last.points_in_tile == 2000);
    // Too little room even for the tile: the error names the tile and the plan's grid, and gives
    // no grid to ask for (a tile job has none).
    BuildOptions tighter = options;
    tighter.max_memory = resident_bytes() + 1'000'000;
    const std::string refused = test::error_text([&] { run_tile(plan, 0, tighter); });
    CHECK(contains(refused, "tile 0 of " + plan.path + " (1000x1000x201 cells of the plan's 4001x4001x201): "));
    CHECK(contains(refused, "plan again with larger cells or smaller tiles, or let the job use more memory"));
    CHECK(!contains(refused, "a grid of"));
    // A plan whose grid no grid may be (edited by hand): refused when read.
    std::string text;
    for (const std::byte b : test::read_file(dir.file("wide.plan.json"))) text.push_back(static_cast<char>(b));
    for (std::size_t at = text.find("4001"); at != std::string::npos; at = text.find("4001", at + 5))
        text.replace(at, 4, "40001");
    std::ofstream(dir.file("edited.plan.json")) << text;
    CHECK(contains(error_text([&] { read_plan(dir.file("edited.plan.json")); }),
                   "its grid of 40001 x 40001 x 201 cells is not one a plan can have"));
    // Its bricks are numbered as the plan's grid numbers them: they lie past x and y 3,896 cells.
    const TileCells cells = read_tile_cells(last.path);
    REQUIRE(!cells.brick_keys.empty());
    const std::uint64_t bricks_x = 4004 / 4, bricks_y = 4004 / 4;
    for (const std::uint64_t key : cells.brick_keys) {
        CHECK(key % bricks_x * 4 >= 3896);
        CHECK(key / bricks_x % bricks_y * 4 >= 3896);
    }
}
