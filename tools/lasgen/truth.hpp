// SPDX-License-Identifier: Apache-2.0
// A mesh against the true surfaces of the scene its points were drawn from, part by part
// (deck, walls, containers, railings, pipes, ...): how far the mesh lies from them, how much of
// each it covers, and how much area it gives each, so that a railing fattened into a tube or the
// two faces of a wall merged into one sheet show as numbers.
//
//     lasgen --scene deck --points 20000000 -o deck.las
//     lasmesh deck.las -o deck.ply
//     lasgen --scene deck --measure deck.ply          # a table by part; --json FILE for JSON
//
// Distances are exact, to the analytic primitives (scene.hpp), not to a sampled cloud.
#pragma once

#include "scene.hpp"

#include "lasmesh/mesh.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace lasgen {

struct TruthOptions {
    std::size_t mesh_samples = 1'000'000;  // points spread over the mesh by area
    std::size_t truth_samples = 1'000'000; // points spread over the true surfaces by area
    double tolerance = 0.05;               // a true point is covered when the mesh comes this near (metres)
    double floating = 0.30;                // mesh farther than this from every true surface floats (metres)
    // World box (min x, y, z, max x, y, z) the mesh was made of: the true surfaces outside it
    // are left out (a mesh of part of the scene, lasmesh --bounds). Empty: the whole scene.
    std::vector<double> within;
};

struct PartError {
    std::string part;
    // Area of the true surfaces a scanner sees (the deck under what stands on it left out;
    // scan shadows counted: the surface is there), and the area of the mesh nearest this part
    // (floating mesh left out). Their ratio is 1 for a faithful mesh, 2 for a railing meshed
    // as a tube twice its width, 0.5 for a wall's two faces meshed as one sheet.
    double truth_area = 0, mesh_area = 0;
    double mean = 0, p99 = 0;  // distance of that mesh to the part's surfaces
    double covered = 0;        // share of the part's true surface (outside shadows) within tolerance
    std::size_t triangles = 0; // the mesh's triangles whose centroid is nearest this part (floating ones left out)
    // Share of those triangles' area, by their winding, facing their nearest surface's free side
    // (Primitive::outside): not the solid's inside, not a plate's middle, not under the deck.
    // Triangles more than 60 degrees from that surface's plane are left out; -1: none left.
    double faces_free_side = -1;
};

struct TruthReport {
    double mesh_area = 0, truth_area = 0;
    std::size_t triangles = 0;                              // the mesh's
    double mean = 0, median = 0, p95 = 0, p99 = 0, max = 0; // mesh to truth, over the mesh area
    double floating_share = 0;                              // of the mesh area, farther than TruthOptions::floating
    double covered = 0;           // share of the true surface (outside shadows) within tolerance
    double faces_free_side = -1;  // over all parts, as PartError's
    double shadows_bridged = -1;  // share of the surface in scan shadows within tolerance; -1: none
    std::vector<PartError> parts; // in the order the scene first names them
};

// The exact distance from a scene-local point to the primitive's surface (for a quad, the
// parallelogram; for a cylinder, its open tube between the two end circles).
double distance_to(const Primitive& primitive, const Vec3& local);

// Measures `mesh` (positions relative to mesh.origin, in the scene's world coordinates) against
// the scene's surfaces. Deterministic: the same mesh gives the same report for any thread count.
TruthReport measure_against_truth(const Scene& scene, const lasmesh::Mesh& mesh, const TruthOptions& options);

// The report as a Markdown table (lengths in centimetres, areas in square metres) and as JSON.
std::string truth_table(const TruthReport& report, const TruthOptions& options);
std::string truth_json(const TruthReport& report, const TruthOptions& options);

} // namespace lasgen
