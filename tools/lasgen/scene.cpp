// SPDX-License-Identifier: Apache-2.0
// Scene construction and per-point sampling. The deck imitates the study's support-vessel scan:
// a tilted deck, thin double-faced walls, railings, pipes and containers, with noise, holes,
// floating outlier clusters and a density that varies several-fold along the deck.
#include "scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lasgen {

namespace {

constexpr double two_pi = 2 * std::numbers::pi;

Vec3 add(const Vec3& a, const Vec3& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Vec3 scaled(const Vec3& a, double s) {
    return {a[0] * s, a[1] * s, a[2] * s};
}
double length(const Vec3& a) {
    return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// SplitMix64 (Steele, Lea, Flood 2014): tiny, fast, and good enough for sampling geometry.
struct Random {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; } // [0,1)
    // Approximately standard normal (Irwin-Hall: four uniforms, rescaled to unit variance),
    // bounded at +-3.46 sigma like a real scanner's noise, and far cheaper than Box-Muller.
    double noise() { return (uniform() + uniform() + uniform() + uniform() - 2.0) * 1.7320508075688772; }
};

Primitive quad(const Vec3& origin, const Vec3& u, const Vec3& v, Rgb8 color, bool holes = false) {
    Primitive p;
    p.kind = PrimitiveKind::quad;
    p.origin = origin, p.u = u, p.v = v, p.color = color, p.can_have_holes = holes;
    p.weight = length(cross(u, v));
    p.outside = scaled(cross(u, v), 1 / p.weight);
    return p;
}

// The quad turned to face away from `solid`, a point on its solid side.
Primitive facing_away(Primitive p, const Vec3& solid) {
    const Vec3 d{p.origin[0] - solid[0], p.origin[1] - solid[1], p.origin[2] - solid[2]};
    if (d[0] * p.outside[0] + d[1] * p.outside[1] + d[2] * p.outside[2] < 0) p.outside = scaled(p.outside, -1);
    return p;
}

// A thin steel plate: both faces are scanned, `thickness` apart along the plate normal.
void plate(std::vector<Primitive>& out, const Vec3& origin, const Vec3& u, const Vec3& v, double thickness,
           Rgb8 color) {
    Vec3 n = cross(u, v);
    n = scaled(n, 0.5 * thickness / length(n));
    out.push_back(facing_away(quad(add(origin, n), u, v, color, true), origin));
    out.push_back(facing_away(quad(add(origin, scaled(n, -1)), u, v, color, true), origin));
}

Primitive cylinder(const Vec3& base, const Vec3& axis, double radius, Rgb8 color) {
    Primitive p;
    p.kind = PrimitiveKind::cylinder;
    p.origin = base, p.u = axis, p.radius = radius, p.color = color;
    Vec3 a = scaled(axis, 1 / length(axis));
    Vec3 helper = std::abs(a[2]) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
    p.v = cross(a, helper);
    p.v = scaled(p.v, 1 / length(p.v));
    p.w = cross(a, p.v);
    p.weight = two_pi * radius * length(axis);
    return p;
}

// A box standing on the deck, scanned on its top and four sides.
void container(std::vector<Primitive>& out, const Vec3& corner, const Vec3& size, Rgb8 color) {
    const double x = size[0], y = size[1], z = size[2];
    const Vec3 centre = add(corner, scaled(size, 0.5));
    out.push_back(facing_away(quad(add(corner, {0, 0, z}), {x, 0, 0}, {0, y, 0}, color), centre));
    out.push_back(facing_away(quad(corner, {x, 0, 0}, {0, 0, z}, color), centre));
    out.push_back(facing_away(quad(add(corner, {0, y, 0}), {x, 0, 0}, {0, 0, z}, color), centre));
    out.push_back(facing_away(quad(corner, {0, y, 0}, {0, 0, z}, color), centre));
    out.push_back(facing_away(quad(add(corner, {x, 0, 0}), {0, y, 0}, {0, 0, z}, color), centre));
}

Primitive round_shape(PrimitiveKind kind, double radius, double minor_radius, Rgb8 color) {
    Primitive p;
    p.kind = kind, p.radius = radius, p.minor_radius = minor_radius, p.color = color;
    p.weight = kind == PrimitiveKind::torus ? 4 * std::numbers::pi * std::numbers::pi * radius * minor_radius
                                            : 4 * std::numbers::pi * radius * radius;
    return p;
}

// Names the part of every primitive from `first` on.
void name_part(std::vector<Primitive>& primitives, std::size_t first, const char* part) {
    for (std::size_t i = first; i < primitives.size(); ++i) primitives[i].part = part;
}

void add_deck(Scene& s) {
    const double length_x = 64, width_y = 24;
    const Rgb8 deck_grey{118, 122, 126}, white{236, 236, 230}, yellow{232, 190, 30}, pipe_blue{62, 104, 160},
        crane_blue{30, 70, 150};
    auto& p = s.primitives;
    p.push_back(quad({0, 0, 0}, {length_x, 0, 0}, {0, width_y, 0}, deck_grey, true));
    name_part(p, 0, "deck");

    // Deckhouse: four thin walls and a roof, each scanned on both faces.
    const double hx = 44, hy = 6, lx = 14, ly = 12, hz = 7, t = 0.03;
    std::size_t first = p.size();
    plate(p, {hx, hy, 0}, {lx, 0, 0}, {0, 0, hz}, t, white);
    plate(p, {hx, hy + ly, 0}, {lx, 0, 0}, {0, 0, hz}, t, white);
    plate(p, {hx, hy, 0}, {0, ly, 0}, {0, 0, hz}, t, white);
    plate(p, {hx + lx, hy, 0}, {0, ly, 0}, {0, 0, hz}, t, white);
    plate(p, {hx, hy, hz}, {lx, 0, 0}, {0, ly, 0}, t, white);
    name_part(p, first, "walls");
    first = p.size();

    container(p, {6, 3, 0}, {12, 2.5, 2.6}, {220, 110, 30});
    container(p, {6, 7, 0}, {6, 2.5, 2.6}, {30, 80, 160});
    container(p, {20, 3, 0}, {6, 2.5, 2.6}, {180, 30, 30});
    container(p, {22, 15, 0}, {6, 2.5, 5.2}, {40, 140, 60});
    name_part(p, first, "containers");
    s.footprints = {{6, 3, 18, 5.5}, {6, 7, 12, 9.5}, {20, 3, 26, 5.5}, {22, 15, 28, 17.5}};

    // Railings along both long edges: top and middle rails, posts every two metres.
    first = p.size();
    for (double y : {0.3, width_y - 0.3}) {
        p.push_back(cylinder({0.5, y, 1.1}, {length_x - 1, 0, 0}, 0.03, yellow));
        p.push_back(cylinder({0.5, y, 0.55}, {length_x - 1, 0, 0}, 0.02, yellow));
        for (double x = 0.5; x <= length_x - 0.5; x += 2) p.push_back(cylinder({x, y, 0}, {0, 0, 1.1}, 0.025, yellow));
    }
    name_part(p, first, "railings");
    // Pipes along the starboard side, a riser, and a crane pedestal.
    first = p.size();
    p.push_back(cylinder({2, 21.5, 0.8}, {38, 0, 0}, 0.25, pipe_blue));
    p.push_back(cylinder({2, 20.8, 1.5}, {38, 0, 0}, 0.12, pipe_blue));
    p.push_back(cylinder({40, 21.5, 0}, {0, 0, 6}, 0.25, pipe_blue));
    name_part(p, first, "pipes");
    p.push_back(cylinder({34, 12, 0}, {0, 0, 5}, 1.2, crane_blue));
    p.back().two_sided = true;
    name_part(p, p.size() - 1, "crane");

    // Scan shadows: no points in these balls on the deck and the deckhouse walls.
    s.holes = {{{10, 12, 0}, 1.5}, {{30, 8, 0}, 2.0}, {{52, 20, 0}, 1.2}, {{48, 6, 3}, 1.0}, {{58, 12, 4}, 1.3}};

    // Floating outlier clusters (spray, birds, stereo mismatches): 0.3% of the points.
    double surface = 0;
    for (const Primitive& q : p) surface += q.weight;
    for (Vec3 centre : {Vec3{15, 12, 9}, Vec3{30, 5, 12}, Vec3{50, 14, 11}}) {
        Primitive ball = round_shape(PrimitiveKind::ball, 0.4, 0, {170, 170, 170});
        ball.origin = centre;
        ball.classification = 7; // LAS class "low point (noise)"
        ball.part = "outliers";
        ball.weight = surface * 0.001;
        p.push_back(ball);
    }
    s.noise_sigma = 0.01;
    s.varying_density = true;
    s.tilt_x = 0.3 * std::numbers::pi / 180; // list
    s.tilt_y = 0.5 * std::numbers::pi / 180; // trim
}

// Rotation about x (list), then about y (trim).
Vec3 tilt(const Scene& s, const Vec3& p) {
    double cx = std::cos(s.tilt_x), sx = std::sin(s.tilt_x), cy = std::cos(s.tilt_y), sy = std::sin(s.tilt_y);
    Vec3 a{p[0], cx * p[1] - sx * p[2], sx * p[1] + cx * p[2]};
    return {cy * a[0] + sy * a[2], a[1], -sy * a[0] + cy * a[2]};
}

// The inverse rotation: back about y, then back about x.
Vec3 untilt(const Scene& s, const Vec3& p) {
    double cx = std::cos(s.tilt_x), sx = std::sin(s.tilt_x), cy = std::cos(s.tilt_y), sy = std::sin(s.tilt_y);
    Vec3 a{cy * p[0] - sy * p[2], p[1], sy * p[0] + cy * p[2]};
    return {a[0], cx * a[1] + sx * a[2], -sx * a[1] + cx * a[2]};
}

// Exact axis-aligned bounds of a primitive after the scene's tilt (a rotation, so it applies to
// directions too). Tight bounds matter: the meshing grid spans the header bounds.
void tilted_bounds(const Scene& s, const Primitive& p, Vec3& lo, Vec3& hi) {
    auto include = [&](const Vec3& centre, const Vec3& reach) {
        Vec3 c = tilt(s, centre);
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a] - reach[a]), hi[a] = std::max(hi[a], c[a] + reach[a]);
    };
    // Half-extent along each axis of a circle of radius r whose plane has unit normal n.
    auto circle_reach = [](const Vec3& n, double r) {
        return Vec3{r * std::sqrt(std::max(0.0, 1 - n[0] * n[0])), r * std::sqrt(std::max(0.0, 1 - n[1] * n[1])),
                    r * std::sqrt(std::max(0.0, 1 - n[2] * n[2]))};
    };
    switch (p.kind) {
    case PrimitiveKind::quad:
        for (const Vec3& corner : {p.origin, add(p.origin, p.u), add(p.origin, p.v), add(add(p.origin, p.u), p.v)})
            include(corner, {0, 0, 0});
        break;
    case PrimitiveKind::cylinder: {
        Vec3 axis = tilt(s, scaled(p.u, 1 / length(p.u)));
        for (const Vec3& end : {p.origin, add(p.origin, p.u)}) include(end, circle_reach(axis, p.radius));
        break;
    }
    case PrimitiveKind::torus: {
        Vec3 ring = circle_reach(tilt(s, {0, 0, 1}), p.radius);
        include(p.origin, add(ring, {p.minor_radius, p.minor_radius, p.minor_radius}));
        break;
    }
    case PrimitiveKind::sphere:
    case PrimitiveKind::ball: include(p.origin, {p.radius, p.radius, p.radius}); break;
    }
}

void finish(Scene& s) {
    double total = 0;
    for (const Primitive& p : s.primitives) total += p.weight;
    double running = 0;
    for (const Primitive& p : s.primitives) s.cumulative.push_back((running += p.weight) / total);
    s.cumulative.back() = 1.0;

    s.min = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
    s.max = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const Primitive& p : s.primitives) tilted_bounds(s, p, s.min, s.max);
    for (int a = 0; a < 3; ++a) {
        s.min[a] += s.origin[a] - 3.5 * s.noise_sigma;
        s.max[a] += s.origin[a] + 3.5 * s.noise_sigma;
    }
}

Vec3 sample_primitive(const Primitive& p, Random& rng) {
    switch (p.kind) {
    case PrimitiveKind::quad: {
        double s = rng.uniform(), t = rng.uniform();
        return add(p.origin, add(scaled(p.u, s), scaled(p.v, t)));
    }
    case PrimitiveKind::cylinder: {
        double h = rng.uniform(), angle = two_pi * rng.uniform();
        Vec3 across = add(scaled(p.v, p.radius * std::cos(angle)), scaled(p.w, p.radius * std::sin(angle)));
        return add(add(p.origin, scaled(p.u, h)), across);
    }
    case PrimitiveKind::sphere: {
        double z = 2 * rng.uniform() - 1, angle = two_pi * rng.uniform(), r = std::sqrt(1 - z * z);
        return add(p.origin, scaled(Vec3{r * std::cos(angle), r * std::sin(angle), z}, p.radius));
    }
    case PrimitiveKind::torus: {
        // Uniform by area: the outer side of the tube is larger, accept by (R + r cos t) / (R + r).
        double t;
        do t = two_pi * rng.uniform();
        while (rng.uniform() * (p.radius + p.minor_radius) > p.radius + p.minor_radius * std::cos(t));
        double phi = two_pi * rng.uniform(), ring = p.radius + p.minor_radius * std::cos(t);
        return add(p.origin, {ring * std::cos(phi), ring * std::sin(phi), p.minor_radius * std::sin(t)});
    }
    case PrimitiveKind::ball: {
        Vec3 q;
        do q = {2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1};
        while (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] > 1);
        return add(p.origin, scaled(q, p.radius));
    }
    }
    return p.origin;
}

bool in_hole(const Scene& s, const Vec3& q) {
    return under_footprint(s, q) || in_shadow(s, q);
}

// Relative point density along the deck: 1 near the scanner station at x = 24 m, falling to
// a fifth at the far end (a cheap bell curve, evaluated for every candidate point).
double density(const Vec3& q) {
    double d = (q[0] - 24) / 10;
    return 0.15 + 0.85 / (1 + d * d);
}

} // namespace

bool under_footprint(const Scene& s, const Vec3& q) {
    for (const auto& [x0, y0, x1, y1] : s.footprints)
        if (q[0] > x0 && q[0] < x1 && q[1] > y0 && q[1] < y1) return true;
    return false;
}

bool in_shadow(const Scene& s, const Vec3& q) {
    for (const Hole& h : s.holes) {
        Vec3 d{q[0] - h.centre[0], q[1] - h.centre[1], q[2] - h.centre[2]};
        if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < h.radius * h.radius) return true;
    }
    return false;
}

Vec3 sample_on(const Primitive& p, std::uint64_t index) {
    Random rng{index * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull};
    rng.next();
    return sample_primitive(p, rng);
}

Vec3 to_world(const Scene& s, const Vec3& local) {
    return add(tilt(s, local), s.origin);
}

Vec3 to_local(const Scene& s, const Vec3& world) {
    return untilt(s, {world[0] - s.origin[0], world[1] - s.origin[1], world[2] - s.origin[2]});
}

SceneKind parse_scene_kind(const std::string& name) {
    if (name == "sphere") return SceneKind::sphere;
    if (name == "box") return SceneKind::box;
    if (name == "torus") return SceneKind::torus;
    if (name == "deck") return SceneKind::deck;
    throw std::invalid_argument("unknown scene '" + name + "' (expected sphere, box, torus or deck)");
}

Scene make_scene(const SceneOptions& o) {
    Scene s;
    s.origin = o.origin;
    const double half = o.size / 2;
    switch (o.kind) {
    case SceneKind::sphere:
        s.name = "sphere";
        s.primitives.push_back(round_shape(PrimitiveKind::sphere, half, 0, o.color));
        break;
    case SceneKind::torus:
        s.name = "torus";
        // Tube radius a fifth of the diameter: a clear hole in the middle.
        s.primitives.push_back(round_shape(PrimitiveKind::torus, half * 0.6, half * 0.4, o.color));
        break;
    case SceneKind::box:
        s.name = "box";
        container(s.primitives, {-half, -half, -half}, {o.size, o.size, o.size}, o.color);
        s.primitives.push_back(facing_away(quad({-half, -half, -half}, {o.size, 0, 0}, {0, o.size, 0}, o.color), {}));
        break;
    case SceneKind::deck:
        s.name = "deck";
        add_deck(s);
        break;
    }
    if (o.noise >= 0) s.noise_sigma = o.noise;
    for (Primitive& p : s.primitives)
        if (p.part.empty()) p.part = s.name;
    finish(s);
    return s;
}

GeneratedPoint generate_point(const Scene& s, std::uint64_t seed, std::uint64_t index) {
    // Seed each point's own stream from (seed, index): the file is the same however it is cut up.
    Random rng{seed * 0xD1B54A32D192ED03ull + index};
    rng.next();
    for (;;) {
        double pick = rng.uniform();
        auto it = std::upper_bound(s.cumulative.begin(), s.cumulative.end(), pick);
        const Primitive& p = s.primitives[std::min<std::size_t>(it - s.cumulative.begin(), s.primitives.size() - 1)];
        Vec3 q = sample_primitive(p, rng);
        if (p.can_have_holes && in_hole(s, q)) continue;
        if (s.varying_density && rng.uniform() > density(q)) continue;
        if (s.noise_sigma > 0)
            for (double& c : q) c += s.noise_sigma * rng.noise();
        q = tilt(s, q);
        return {add(q, s.origin), p.color, p.classification};
    }
}

} // namespace lasgen
