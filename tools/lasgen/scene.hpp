// SPDX-License-Identifier: Apache-2.0
// Synthetic scenes made of simple primitives, sampled one point at a time. Every point depends
// only on (seed, index), so any block size or thread count gives the same file.
#pragma once

#include "lasmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lasgen {

using lasmesh::Vec3;
using Rgb8 = std::array<std::uint8_t, 3>;

enum class SceneKind { sphere, box, torus, deck };

struct GeneratedPoint {
    Vec3 position; // world coordinates (scene origin added)
    Rgb8 color;
    std::uint8_t classification;
};

enum class PrimitiveKind { quad, cylinder, sphere, torus, ball };

// quad: origin + s*u + t*v for s, t in [0,1]. cylinder: base `origin`, axis `u` (its full
// length), `v` and `w` unit vectors across. sphere and ball: centre `origin`, `radius`.
// torus: centre `origin`, axis z, `radius` to the tube centre, `minor_radius` of the tube.
struct Primitive {
    PrimitiveKind kind = PrimitiveKind::quad;
    Vec3 origin{}, u{}, v{}, w{};
    double radius = 0, minor_radius = 0;
    Rgb8 color{};
    std::uint8_t classification = 1;
    // What the primitive is part of ("deck", "railings", ...), for errors by part
    // (truth.hpp); "outliers" are not a surface.
    std::string part;
    bool can_have_holes = false;
    double weight = 0; // share of the points, relative to the other primitives
    // A quad's unit normal on the side of its free space (the other side is solid: the deck's
    // underside, a container's inside, a plate's middle), which a mesh of it should face. Round
    // shapes are solid inside: they face away from their axis or centre.
    Vec3 outside{};
    // Both sides are free space (the crane's pedestal: open at the top, the deck inside it
    // scanned): a mesh of it may face either way.
    bool two_sided = false;
};

struct Hole {
    Vec3 centre;
    double radius;
};

struct Scene {
    std::string name;
    Vec3 origin{}; // added to every local coordinate
    std::vector<Primitive> primitives;
    std::vector<double> cumulative; // normalised running sum of weights, one per primitive
    std::vector<Hole> holes;        // no points inside these balls (scan shadows)
    // Footprints (x0, y0, x1, y1) of what stands on the deck: no deck points under them, as no
    // scanner sees the deck under a container.
    std::vector<std::array<double, 4>> footprints;
    double noise_sigma = 0;        // near-gaussian noise per axis, bounded at 3.46 sigma
    bool varying_density = false;  // several-fold denser in the middle of the deck than at its ends
    double tilt_x = 0, tilt_y = 0; // radians, applied to the whole scene (a ship's trim and list)
    Vec3 min{}, max{};             // bounds that contain every point the scene can produce
};

struct SceneOptions {
    SceneKind kind = SceneKind::deck;
    double size = 10;  // shapes: diameter (sphere, torus) or edge (box), in metres
    double noise = -1; // metres; negative: the scene's default
    Vec3 origin{};
    Rgb8 color{200, 80, 40}; // single shapes only
};

Scene make_scene(const SceneOptions& options);
GeneratedPoint generate_point(const Scene& scene, std::uint64_t seed, std::uint64_t index);

// A point spread uniformly by area over the primitive's surface (its volume for a ball),
// depending only on `index`; no noise, no tilt.
Vec3 sample_on(const Primitive& primitive, std::uint64_t index);
// Scene coordinates (before tilt and origin) to world coordinates, and back.
Vec3 to_world(const Scene& scene, const Vec3& local);
Vec3 to_local(const Scene& scene, const Vec3& world);
// A local point under something standing on the deck, where no scanner sees the deck.
bool under_footprint(const Scene& scene, const Vec3& local);
// A local point in a scan shadow: the surface is there, the scan has no points of it.
bool in_shadow(const Scene& scene, const Vec3& local);
SceneKind parse_scene_kind(const std::string& name); // throws std::invalid_argument

} // namespace lasgen
