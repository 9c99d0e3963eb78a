// SPDX-License-Identifier: Apache-2.0
// Internal: marching cubes over the bricks of a lattice that hold surface, for any sampled field.
//
// Passes in the spirit of flying edges (Schroeder et al. 2015), over bricks instead of layers:
// sample each active brick's own lattice points once, count the vertices and triangles of each
// brick, prefix-sum the counts in ascending brick order, then fill preallocated arrays. Each
// brick also keeps a bitmask of the lattice edges that got a vertex, so a triangle finds the
// vertex of an edge in a neighbouring brick as that brick's first vertex plus a population count:
// no locks, no hash map, and the same mesh for any number of threads.
//
// A field may leave samples undefined (far from the data) and may reject a crossing (two samples
// of opposite sign that belong to surfaces which do not meet): a cube is meshed only when its
// eight samples are defined and every crossing on its edges is accepted, and an edge gets a vertex
// only when a meshed cube uses it. The result is then a manifold with boundary: its boundary runs
// where the field stops. A field whose samples are undefined at every lattice point outside the
// active bricks says so (`static constexpr bool undefined_outside_active = true`): the points of
// an inactive neighbour are then not sampled at all.
#pragma once

#include "grid/cell_sums.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/mesh.hpp"
#include "mesh/marching_cubes_table.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace lasmesh::detail {

struct FieldSample {
    float value = 0;
    std::uint32_t source = 0; // which part of the data decided the value (the field's business)
    bool defined = false;
    bool inside = false;
};

// A FieldSample in 8 bytes, as pass 0 keeps it: the flags in the source's top two bits.
struct StoredSample {
    static constexpr std::uint32_t source_limit = 1u << 30;
    float value; // no initialisers: an array of them takes memory only where written
    std::uint32_t source_and_flags;

    static StoredSample of(const FieldSample& s) {
        return {s.value, s.source | std::uint32_t{s.defined} << 31 | std::uint32_t{s.inside} << 30};
    }
    FieldSample sample() const {
        return {value, source_and_flags & (source_limit - 1), (source_and_flags >> 31) != 0,
                ((source_and_flags >> 30) & 1) != 0};
    }
};

struct VertexOut {
    std::array<float, 3> position{};
    std::array<float, 3> normal{};
    std::array<std::uint8_t, 3> color{};
    float offset = 0; // a value of the field's own, per vertex (kept when run is given `offsets`)
};

// The lattice and the bricks of it to visit: every cube and edge that can carry surface must have
// its lower corner in an active brick.
struct LatticeBricks {
    static constexpr int bits = 2;
    static constexpr std::int64_t size = 1 << bits;
    std::array<std::int64_t, 3> points{}; // lattice points per axis
    std::array<std::int64_t, 3> bricks{}; // bricks per axis
    std::vector<std::uint64_t> active;    // linear brick keys (x fastest), ascending, unique

    explicit LatticeBricks(std::array<std::int64_t, 3> lattice_points) : points(lattice_points) {
        for (int a = 0; a < 3; ++a) bricks[a] = (points[a] + size - 1) / size;
    }
    std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) const {
        return (std::uint64_t(z) * bricks[1] + std::uint64_t(y)) * bricks[0] + std::uint64_t(x);
    }
};

// Field: sampler(first, n), an object whose sample(x, y, z) gives the sample at the lattice
// points first + [0, n) on each axis (outside the lattice too: undefined);
// bool accepts(a, b) for two defined samples of which one is inside; and
// void vertex(p, axis, a, b, VertexOut&) for the crossing on the edge from p along axis.
template <class Field>
class SparseMarchingCubes {
  public:
    SparseMarchingCubes(const Field& field, const LatticeBricks& lattice) : f_(field), l_(lattice) {}

    // `sampled`, when given, is called once the field's samplers are done with (after pass 0, for
    // a field undefined outside the active bricks): what only they read may go.
    // `offsets`, when given, receives each vertex's VertexOut::offset.
    Mesh run(bool colored, const std::function<void()>& sampled = {}, std::vector<float>* offsets = nullptr) {
        const std::size_t n = l_.active.size();
        // Position of each active brick in `active`, + 1 (0: not active).
        slot_ = BrickTable(l_.active);

        // Pass 0: the samples at each active brick's own B^3 lattice points. A brick's cubes also
        // need its neighbours' points next to it: taken from here, each point sampled once
        // (sampling a brick with its apron took 3.4 times the points, twice over).
        // Only the bricks with a defined sample keep theirs (60% of the deck's at grid 2048), in
        // blocks handed out as they come: where a block lies changes no output. The blocks are
        // allocated for every brick but not initialised, so only the pages written are taken.
        block_of_.assign(n, no_block);
        blocks_.reset(new StoredSample[n * cells]);
        std::atomic<std::uint32_t> blocks_used{0};
        tbb::parallel_for(std::size_t{0}, n, [&](std::size_t b) {
            const auto origin = origin_of(l_.active[b]);
            const auto sampler = f_.sampler(origin, B);
            if constexpr (requires { sampler.empty; })
                if (sampler.empty) return; // nothing defined near the brick
            std::array<StoredSample, cells> block;
            bool any_defined = false;
            for (int p = 0; p < cells; ++p) {
                const FieldSample s = sampler.sample(origin[0] + p % B, origin[1] + p / B % B, origin[2] + p / (B * B));
                if (s.source >= StoredSample::source_limit)
                    throw Error(ErrorKind::usage, "the surface has more than 2^30 sources (cells); use a coarser grid",
                                "grid");
                block[p] = StoredSample::of(s);
                any_defined |= s.defined;
            }
            if (!any_defined) return;
            const std::uint32_t at = blocks_used.fetch_add(1, std::memory_order_relaxed);
            std::copy(block.begin(), block.end(), blocks_.get() + std::size_t{at} * cells);
            block_of_[b] = at;
        });
        if constexpr (requires { requires Field::undefined_outside_active; })
            if (sampled) sampled();
        masks_.assign(n, {});
        std::vector<std::uint64_t> vertices_in(n + 1, 0), triangles_in(n + 1, 0);
        const CaseTable& table = case_table();

        // Pass 1: per brick, the edges that get a vertex and the triangles of its cubes.
        tbb::parallel_for(std::size_t{0}, n, [&](std::size_t b) {
            // Every cube and edge of a brick starts at one of its own points: none defined, none meshed.
            if (block_of_[b] == no_block) return;
            Brick brick(*this, b);
            std::uint64_t t = 0;
            for (int p = 0; p < cells; ++p)
                if (brick.meshed(p)) t += table.triangles[brick.cube_case(p)].size();
            auto& mask = masks_[b];
            for (int p = 0; p < cells; ++p)
                for (int a = 0; a < 3; ++a)
                    if (brick.needs_vertex(p, a)) mask[(p * 3 + a) / 64] |= std::uint64_t{1} << ((p * 3 + a) % 64);
            vertices_in[b + 1] = std::popcount(mask[0]) + std::popcount(mask[1]) + std::popcount(mask[2]);
            triangles_in[b + 1] = t;
        });
        // Pass 2: prefix sums give each brick its place in the output.
        for (std::size_t b = 0; b < n; ++b) {
            vertices_in[b + 1] += vertices_in[b];
            triangles_in[b + 1] += triangles_in[b];
        }
        if (vertices_in[n] > UINT32_MAX)
            throw Error(ErrorKind::usage, "the mesh would have more than 2^32 vertices; use a coarser grid", "grid");
        first_vertex_ = vertices_in;

        Mesh mesh;
        mesh.positions.resize(vertices_in[n]);
        mesh.normals.resize(vertices_in[n]);
        if (colored) mesh.colors.resize(vertices_in[n]);
        if (offsets) offsets->assign(vertices_in[n], 0);
        mesh.triangles.resize(triangles_in[n]);
        const CubeEdges& edges = cube_edges();

        // Pass 3: fill vertices and triangles, each brick at its own offsets.
        tbb::parallel_for(std::size_t{0}, n, [&](std::size_t b) {
            // Most bricks around the data hold nothing: not assembled again.
            if (vertices_in[b + 1] == vertices_in[b] && triangles_in[b + 1] == triangles_in[b]) return;
            Brick brick(*this, b);
            std::uint64_t v = vertices_in[b];
            for (int p = 0; p < cells; ++p)
                for (int a = 0; a < 3; ++a) {
                    if (!(masks_[b][(p * 3 + a) / 64] >> ((p * 3 + a) % 64) & 1)) continue;
                    const auto q = brick.global(p);
                    VertexOut out;
                    f_.vertex(q, a, brick.sample(p, 0, 0, 0), brick.sample(p, a == 0, a == 1, a == 2), out);
                    mesh.positions[v] = out.position;
                    mesh.normals[v] = out.normal;
                    if (colored) mesh.colors[v] = out.color;
                    if (offsets) (*offsets)[v] = out.offset;
                    ++v;
                }
            std::uint64_t t = triangles_in[b];
            for (int p = 0; p < cells; ++p) {
                if (!brick.meshed(p)) continue;
                const auto q = brick.global(p);
                for (const auto& tri : table.triangles[brick.cube_case(p)]) {
                    for (int k = 0; k < 3; ++k) {
                        const int e = tri[k], corner = edges.corners[e][0];
                        mesh.triangles[t][k] = vertex_id(q[0] + (corner & 1), q[1] + ((corner >> 1) & 1),
                                                         q[2] + ((corner >> 2) & 1), e / 4);
                    }
                    ++t;
                }
            }
        });
        return mesh;
    }

  private:
    static constexpr std::int64_t B = LatticeBricks::size;
    static constexpr int cells = B * B * B;
    static constexpr std::int64_t S = B + 2; // samples per axis: the brick and one more each side
    static_assert(cells * 3 <= 192, "a brick's edges must fit its three-word mask");

    std::array<std::int64_t, 3> origin_of(std::uint64_t key) const {
        return {std::int64_t(key % l_.bricks[0]) * B, std::int64_t(key / l_.bricks[0] % l_.bricks[1]) * B,
                std::int64_t(key / l_.bricks[0] / l_.bricks[1]) * B};
    }

    // One brick's samples (with a one-point apron) and which of its cubes are meshed.
    struct Brick {
        const SparseMarchingCubes& m;
        std::array<std::int64_t, 3> origin;
        std::array<FieldSample, S * S * S> samples;
        std::array<bool, (B + 1) * (B + 1) * (B + 1)> meshed_cube; // min corners -1 .. B-1

        // The active brick `index`: its samples and its neighbours' next to it, from pass 0.
        Brick(const SparseMarchingCubes& owner, std::size_t index) : m(owner) {
            const auto& l = owner.l_;
            origin = owner.origin_of(l.active[index]);
            constexpr bool undefined_outside = requires {
                requires Field::undefined_outside_active;
            };
            std::array<bool, S * S * S> to_sample{}; // points of inactive neighbours, for the field
            bool any_to_sample = false;
            // The window's part in neighbour (dx, dy, dz) of the brick: local -1, 0 .. B-1, or B.
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const std::array<std::int64_t, 3> brick{origin[0] / B + dx, origin[1] / B + dy,
                                                                origin[2] / B + dz};
                        const bool in_lattice = brick[0] >= 0 && brick[1] >= 0 && brick[2] >= 0 &&
                                                brick[0] < l.bricks[0] && brick[1] < l.bricks[1] &&
                                                brick[2] < l.bricks[2];
                        const std::uint32_t slot =
                            in_lattice ? owner.slot_.find(l.key(brick[0], brick[1], brick[2])) : 0;
                        const std::uint32_t block = slot ? owner.block_of_[slot - 1] : no_block;
                        const StoredSample* from =
                            block != no_block ? owner.blocks_.get() + std::size_t{block} * cells : nullptr;
                        // An active brick without a block has no defined sample.
                        const bool known = slot != 0;
                        const std::array<int, 3> d{dx, dy, dz};
                        std::array<std::int64_t, 3> lo{}, hi{};
                        for (int a = 0; a < 3; ++a)
                            lo[a] = d[a] < 0 ? -1 : d[a] == 0 ? 0 : B, hi[a] = d[a] < 0 ? -1 : d[a] == 0 ? B - 1 : B;
                        for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
                            for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
                                for (std::int64_t x = lo[0]; x <= hi[0]; ++x) {
                                    const std::size_t at = static_cast<std::size_t>(((z + 1) * S + y + 1) * S + x + 1);
                                    if (from) {
                                        samples[at] =
                                            from[((z - dz * B) * B + (y - dy * B)) * B + (x - dx * B)].sample();
                                    } else {
                                        samples[at] = {}; // undefined, unless the field is asked below
                                        if (in_lattice && !known && !undefined_outside)
                                            to_sample[at] = any_to_sample = true;
                                    }
                                }
                    }
            if (any_to_sample) {
                const auto sampler = owner.f_.sampler({origin[0] - 1, origin[1] - 1, origin[2] - 1}, S);
                for (std::int64_t z = 0; z < S; ++z)
                    for (std::int64_t y = 0; y < S; ++y)
                        for (std::int64_t x = 0; x < S; ++x)
                            if (to_sample[static_cast<std::size_t>((z * S + y) * S + x)])
                                samples[static_cast<std::size_t>((z * S + y) * S + x)] =
                                    sampler.sample(origin[0] + x - 1, origin[1] + y - 1, origin[2] + z - 1);
            }
            for (std::int64_t z = -1; z < B; ++z)
                for (std::int64_t y = -1; y < B; ++y)
                    for (std::int64_t x = -1; x < B; ++x)
                        meshed_cube[((z + 1) * (B + 1) + y + 1) * (B + 1) + x + 1] = compute_meshed(x, y, z);
        }
        // Sample at local (x, y, z), each in -1 .. B.
        const FieldSample& at(std::int64_t x, std::int64_t y, std::int64_t z) const {
            return samples[((z + 1) * S + y + 1) * S + x + 1];
        }
        static std::array<std::int64_t, 3> local(int p) { return {p % B, p / B % B, p / (B * B)}; }
        std::array<std::int64_t, 3> global(int p) const {
            const auto q = local(p);
            return {origin[0] + q[0], origin[1] + q[1], origin[2] + q[2]};
        }
        const FieldSample& sample(int p, int dx, int dy, int dz) const {
            const auto q = local(p);
            return at(q[0] + dx, q[1] + dy, q[2] + dz);
        }
        bool in_lattice(std::int64_t x, std::int64_t y, std::int64_t z) const {
            const auto& pts = m.l_.points;
            return origin[0] + x >= 0 && origin[1] + y >= 0 && origin[2] + z >= 0 && origin[0] + x < pts[0] &&
                   origin[1] + y < pts[1] && origin[2] + z < pts[2];
        }
        int case_at(std::int64_t x, std::int64_t y, std::int64_t z) const {
            int mask = 0;
            for (int c = 0; c < 8; ++c) mask |= at(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1)).inside << c;
            return mask;
        }
        bool compute_meshed(std::int64_t x, std::int64_t y, std::int64_t z) const {
            if (!in_lattice(x, y, z) || !in_lattice(x + 1, y + 1, z + 1)) return false;
            for (int c = 0; c < 8; ++c)
                if (!at(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1)).defined) return false;
            const int mask = case_at(x, y, z);
            if (mask == 0 || mask == 255) return false;
            const CubeEdges& edges = cube_edges();
            for (int e = 0; e < 12; ++e) {
                const int c0 = edges.corners[e][0], c1 = edges.corners[e][1];
                const FieldSample& a = at(x + (c0 & 1), y + ((c0 >> 1) & 1), z + ((c0 >> 2) & 1));
                const FieldSample& b = at(x + (c1 & 1), y + ((c1 >> 1) & 1), z + ((c1 >> 2) & 1));
                if (a.inside != b.inside && !m.f_.accepts(a, b)) return false;
            }
            return true;
        }
        bool meshed_local(std::int64_t x, std::int64_t y, std::int64_t z) const {
            return meshed_cube[((z + 1) * (B + 1) + y + 1) * (B + 1) + x + 1];
        }
        bool meshed(int p) const {
            const auto q = local(p);
            return meshed_local(q[0], q[1], q[2]);
        }
        int cube_case(int p) const {
            const auto q = local(p);
            return case_at(q[0], q[1], q[2]);
        }
        // The edge from p along axis a gets a vertex when it is crossed and a meshed cube uses it.
        bool needs_vertex(int p, int a) const {
            const auto q = local(p);
            const FieldSample& s0 = at(q[0], q[1], q[2]);
            const FieldSample& s1 = at(q[0] + (a == 0), q[1] + (a == 1), q[2] + (a == 2));
            if (!s0.defined || !s1.defined || s0.inside == s1.inside) return false;
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            for (int s = 0; s < 2; ++s)
                for (int t = 0; t < 2; ++t) {
                    std::array<std::int64_t, 3> min = q;
                    min[b] -= s;
                    min[c] -= t;
                    if (meshed_local(min[0], min[1], min[2])) return true;
                }
            return false;
        }
    };

    std::uint32_t vertex_id(std::int64_t x, std::int64_t y, std::int64_t z, int axis) const {
        const std::uint64_t b = slot_.find(l_.key(x / B, y / B, z / B)) - 1;
        const int bit = static_cast<int>((((z % B) * B + y % B) * B + x % B) * 3 + axis);
        const auto& mask = masks_[b];
        std::uint64_t before = 0;
        for (int w = 0; w < bit / 64; ++w) before += std::popcount(mask[w]);
        before += std::popcount(mask[bit / 64] & ((std::uint64_t{1} << (bit % 64)) - 1));
        return static_cast<std::uint32_t>(first_vertex_[b] + before);
    }

    const Field& f_;
    const LatticeBricks& l_;
    BrickTable slot_;
    std::vector<std::array<std::uint64_t, 3>> masks_;
    // Pass 0's samples: B^3 a block (x fastest), the block of active brick b at block_of_[b].
    static constexpr std::uint32_t no_block = UINT32_MAX;
    std::vector<std::uint32_t> block_of_;
    std::unique_ptr<StoredSample[]> blocks_;
    std::vector<std::uint64_t> first_vertex_;
};

// The bricks of a lattice of `points` that hold every lattice point within `reach` below and
// reach + 1 above a cell of the grid's bricks `keys` (a lattice of cell centres, padded, has
// reach 0; one of corners sampled a cell beyond the corners of occupied cells has reach 1).
inline LatticeBricks lattice_near_bricks(const CellGrid& grid, const std::vector<std::uint64_t>& keys,
                                         std::array<std::int64_t, 3> points, int reach) {
    LatticeBricks lattice(points);
    static_assert(LatticeBricks::size == CellGrid::brick_size, "lattice and grid bricks align");
    std::vector<std::uint64_t>& active = lattice.active;
    for (std::uint64_t key : keys) {
        const std::int64_t bx = key % grid.bricks[0], by = key / grid.bricks[0] % grid.bricks[1],
                           bz = key / grid.bricks[0] / grid.bricks[1];
        for (std::int64_t z = bz - reach; z <= bz + 1; ++z)
            for (std::int64_t y = by - reach; y <= by + 1; ++y)
                for (std::int64_t x = bx - reach; x <= bx + 1; ++x)
                    if (x >= 0 && y >= 0 && z >= 0 && x < lattice.bricks[0] && y < lattice.bricks[1] &&
                        z < lattice.bricks[2])
                        active.push_back(lattice.key(x, y, z));
    }
    std::sort(active.begin(), active.end());
    active.erase(std::unique(active.begin(), active.end()), active.end());
    return lattice;
}

// The same around every occupied brick.
inline LatticeBricks lattice_near_data(const CellGrid& grid, std::array<std::int64_t, 3> points, int reach = 0) {
    return lattice_near_bricks(grid, grid.brick_keys, points, reach);
}

template <class Field>
Mesh march_sparse(const Field& field, const LatticeBricks& lattice, bool colored,
                  const std::function<void()>& sampled = {}, std::vector<float>* offsets = nullptr) {
    return SparseMarchingCubes<Field>(field, lattice).run(colored, sampled, offsets);
}

} // namespace lasmesh::detail
