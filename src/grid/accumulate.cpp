// accumulate_density: streams raw records to the device in double-buffered slices and runs
// kernels/accumulate.cl over each; the host reads records straight into the device's slice
// buffers (mapped, so a device that shares host memory copies nothing) and keeps the pool of
// bricks large enough for every slice before the slice's points are added.
#include "lasmesh/grid/density_grid.hpp"

#include "kernel_sources.hpp"
#include "lasmesh/error.hpp"
#include "opencl_device.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace lasmesh {

namespace {

// Measured on PoCL (docs/benchmarks.md): 4-16 MiB slices stay in cache and beat 64 MiB ones.
constexpr std::uint64_t default_slice_bytes = 16ull << 20;
constexpr std::size_t slots = 2; // one slice being read while the device works on the other
// Records one work-item sums before it flushes: long enough to merge the runs of a scan in
// acquisition order, short enough to keep every core busy on a small slice.
constexpr unsigned run_length = 32;
constexpr std::uint64_t first_pool_bricks = 1024;

std::string mib(std::uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", bytes / 1048576.0);
    return text;
}

std::string dims_text(const GridSpec& g) {
    return std::to_string(g.dims[0]) + "x" + std::to_string(g.dims[1]) + "x" + std::to_string(g.dims[2]);
}

std::uint64_t cell_words(bool color) { return color ? 8 : 4; }

std::array<std::uint32_t, 3> brick_dims(const GridSpec& grid) {
    std::array<std::uint32_t, 3> b{};
    for (int a = 0; a < 3; ++a)
        b[a] = static_cast<std::uint32_t>((grid.dims[a] + DensityGrid::brick_size - 1) / DensityGrid::brick_size);
    return b;
}

std::uint64_t brick_count(const GridSpec& grid) {
    const auto b = brick_dims(grid);
    return std::uint64_t{b[0]} * b[1] * b[2];
}

struct Limits {
    std::uint64_t global_memory, max_alloc, max_memory;
};

// Empty when `need` fits; otherwise what it exceeds.
std::string exceeded(const MemoryNeed& need, const Limits& limits, const std::string& what) {
    if (need.largest_buffer > limits.max_alloc)
        return what + " needs " + mib(need.largest_buffer) + ", more than the device's largest allocation (" +
               mib(limits.max_alloc) + ")";
    if (need.device_bytes > limits.global_memory)
        return "it needs " + mib(need.device_bytes) + " of device memory, more than the device has (" +
               mib(limits.global_memory) + ")";
    if (limits.max_memory && need.device_bytes + need.host_bytes > limits.max_memory)
        return "it needs " + mib(need.device_bytes + need.host_bytes) +
               " on host and device together, more than --max-memory (" + mib(limits.max_memory) + ")";
    return {};
}

// The largest N along the longest axis for which `fits(grid)` holds (memory grows with N).
template <class Fits>
std::uint32_t largest_fitting_grid(const LasHeader& header, const AccumulateOptions& options, std::uint32_t upper, Fits fits) {
    std::uint32_t lo = 0, hi = upper;
    while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo + 1) / 2;
        AccumulateOptions trial = options;
        trial.grid = GridRequest{GridRequest::Kind::longest_axis, {mid, 0, 0}, 0};
        if (fits(grid_for(header, trial)))
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

std::uint32_t longest_dim(const GridSpec& g) { return std::max({g.dims[0], g.dims[1], g.dims[2]}); }

void check_index_memory(const LasHeader& header, const AccumulateOptions& options, const GridSpec& grid,
                        std::uint64_t slice_bytes, const Limits& limits) {
    const std::string problem = exceeded(memory_need(grid, slice_bytes), limits, "the brick index");
    if (problem.empty()) return;
    const std::uint32_t fit = largest_fitting_grid(header, options, longest_dim(grid), [&](const GridSpec& g) {
        return exceeded(memory_need(g, slice_bytes), limits, "").empty();
    });
    throw Error(ErrorKind::usage, "the grid " + dims_text(grid) + " (" + std::to_string(grid.cell_count()) +
                                      " cells) does not fit: " + problem +
                                      (fit > 0 ? "; --grid " + std::to_string(fit) + " would fit" : ""));
}

// The pool of bricks outgrew a limit after `points_read` of the header's points: stop, and
// suggest a grid whose pool would fit, assuming the surface's bricks fall with the square of the
// grid.
[[noreturn]] void pool_too_large(const LasHeader& header, const AccumulateOptions& options, const GridSpec& grid,
                                 const std::string& problem, std::uint64_t bricks_used, std::uint64_t points_read,
                                 std::uint64_t available_bytes) {
    // A scan in acquisition order meets new bricks all along; a random order meets most of them
    // early. Between the two: at most twice the bricks seen so far.
    const double seen = std::max<double>(1, static_cast<double>(points_read)) / std::max<double>(1, header.point_count);
    const double growth = std::min(2.0, 1 / std::min(1.0, seen));
    // A brick costs its bytes up to three times on the device while the pool doubles (old and
    // new buffer), and about once more on the host when it is read back.
    const double projected = static_cast<double>(bricks_used * brick_device_bytes(has_color(header))) * growth * 4;
    const double shrink = std::sqrt(static_cast<double>(available_bytes) / std::max(1.0, projected));
    const auto fit = static_cast<std::uint32_t>(std::floor(longest_dim(grid) * std::min(0.9, shrink * 0.9)));
    throw Error(ErrorKind::usage, "the grid " + dims_text(grid) + " does not fit: after " + std::to_string(points_read) +
                                      " of " + std::to_string(header.point_count) + " points its surface fills " +
                                      std::to_string(bricks_used) + " bricks and " + problem +
                                      (fit > 0 ? "; --grid " + std::to_string(fit) + " would fit" : "") +
                                      " (nothing was written)");
    (void)options;
}

} // namespace

std::uint64_t brick_device_bytes(bool has_color) { return DensityGrid::brick_cells * cell_words(has_color) * 8; }

std::uint64_t DensityGrid::occupied_cells() const {
    return static_cast<std::uint64_t>(std::count_if(cells.begin(), cells.end(), [](const CellSums& c) { return c.count > 0; }));
}

Rgb8 DensityGrid::mean_color(const CellSums& cell) const {
    const std::uint64_t n = cell.count;
    if (n == 0 || !has_color()) return {0, 0, 0};
    // Rounded integer division; 128-bit so no count or sum can overflow.
    const unsigned __int128 divisor = static_cast<unsigned __int128>(n) * (color_is_16bit() ? 257 : 1);
    auto mean = [&](std::uint64_t sum) {
        return static_cast<std::uint8_t>((2 * static_cast<unsigned __int128>(sum) + divisor) / (2 * divisor));
    };
    return {mean(cell.color[0]), mean(cell.color[1]), mean(cell.color[2])};
}

Vec3 DensityGrid::centroid(const std::array<std::int64_t, 3>& cell, const CellSums& sums) const {
    Vec3 p{};
    for (int a = 0; a < 3; ++a) {
        const double raw = static_cast<double>(axes[a].starts[cell[a]]) +
                           static_cast<double>(sums.position[a]) / static_cast<double>(std::max<std::uint64_t>(1, sums.count));
        p[a] = raw * scale[a] + offset[a] - spec.origin[a];
    }
    return p;
}

MemoryNeed memory_need(const GridSpec& grid, std::uint64_t slice_bytes) {
    MemoryNeed need;
    const std::uint64_t index_bytes = brick_count(grid) * 4;
    need.largest_buffer = index_bytes;
    // The index, the slices and the list of bricks new in a slice (at most one per record).
    need.device_bytes = index_bytes + slots * slice_bytes + slice_bytes / 4;
    // The index read back; the slices are mapped device memory.
    need.host_bytes = index_bytes;
    return need;
}

GridSpec grid_for(const LasHeader& header, const AccumulateOptions& options) {
    return make_grid_spec(options.bounds.value_or(Bounds{header.min, header.max}), options.grid);
}

DensityGrid accumulate_density(LasReader& reader, ComputeDevice& device, const AccumulateOptions& options) {
    const LasHeader& header = reader.header();
    ComputeDevice::Impl& dev = device.impl();
    const std::size_t length = header.point_record_length;
    const bool color = has_color(header);

    DensityGrid out;
    out.spec = grid_for(header, options);
    out.color = color;
    out.scale = header.scale;
    out.offset = header.offset;
    out.bricks = brick_dims(out.spec);
    const std::uint64_t max_alloc = options.max_alloc ? std::min(options.max_alloc, dev.info.max_alloc) : dev.info.max_alloc;
    const std::uint64_t slice_limit = std::min(options.slice_bytes ? options.slice_bytes : default_slice_bytes, max_alloc);
    // No larger than the records still to come: a small file needs no 16 MiB slices.
    const std::size_t slice_records = static_cast<std::size_t>(
        std::clamp<std::uint64_t>(std::min<std::uint64_t>(slice_limit / length, reader.records_left()), 1, 1u << 30));
    const std::size_t slice_bytes = slice_records * length;
    const Limits limits{dev.info.global_memory, max_alloc, options.max_memory};
    check_index_memory(header, options, out.spec, slice_bytes, limits);
    for (int a = 0; a < 3; ++a) out.axes[a] = axis_cells(out.spec, a, header.scale[a], header.offset[a]);

    const std::uint64_t bricks = brick_count(out.spec);
    const std::uint64_t brick_bytes = brick_device_bytes(color);
    const MemoryNeed fixed = memory_need(out.spec, slice_bytes);
    std::vector<std::uint32_t> slot_of_brick;
    std::vector<std::byte> pool_copy_block;
    std::uint64_t used = 0;
    cl::Buffer pool;

    try {
        cl::Context& ctx = dev.context;
        cl::CommandQueue& queue = dev.queue;
        std::string defines = "-D BRICK_BITS=" + std::to_string(DensityGrid::brick_bits) + " -D RUN=" + std::to_string(run_length);
        if (color) defines += " -D RGB_OFFSET=" + std::to_string(rgb_offset(header.point_format));
        cl::Program program = build_program(dev, "accumulate.cl", kernels::accumulate, defines);
        cl::Kernel add(program, "accumulate"), mark(program, "mark_bricks"), assign(program, "assign_bricks"),
            add_listed(program, "accumulate_listed");

        cl::Buffer index(ctx, CL_MEM_READ_WRITE, bricks * 4);
        queue.enqueueFillBuffer(index, cl_uint{0}, 0, bricks * 4);
        // The points of a slice whose bricks were new, and the bricks they claimed: each at most
        // one per record.
        cl::Buffer deferred(ctx, CL_MEM_READ_WRITE, slice_records * 4);
        cl::Buffer new_bricks(ctx, CL_MEM_READ_WRITE, slice_records * 4);
        cl::Buffer deferred_count(ctx, CL_MEM_READ_WRITE, sizeof(cl_uint)), new_count(ctx, CL_MEM_READ_WRITE, sizeof(cl_uint));
        queue.enqueueFillBuffer(deferred_count, cl_uint{0}, 0, sizeof(cl_uint));
        queue.enqueueFillBuffer(new_count, cl_uint{0}, 0, sizeof(cl_uint));
        cl::Buffer stats(ctx, CL_MEM_READ_WRITE, 4 * sizeof(cl_uint));
        queue.enqueueFillBuffer(stats, cl_uint{0}, 0, 4 * sizeof(cl_uint));
        std::uint64_t capacity = std::min<std::uint64_t>(first_pool_bricks, std::max<std::uint64_t>(1, bricks));
        pool = cl::Buffer(ctx, CL_MEM_READ_WRITE, capacity * brick_bytes);
        queue.enqueueFillBuffer(pool, cl_ulong{0}, 0, capacity * brick_bytes);

        // The grid's arguments (starts, cell counts, cells per raw unit, bricks along x and y) and
        // the index come at the same place in each kernel, after `first` others.
        std::array<cl::Buffer, 3> starts_buffers; // kernel arguments do not keep buffers alive
        const std::array<std::pair<cl::Kernel*, int>, 3> with_grid{{{&add, 3}, {&mark, 4}, {&add_listed, 4}}};
        for (int a = 0; a < 3; ++a) {
            std::vector<cl_long> starts(out.axes[a].starts.begin(), out.axes[a].starts.end());
            starts_buffers[a] = cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, starts.size() * sizeof(cl_long),
                                           starts.data());
            const double raw_span = static_cast<double>(starts.back() - starts.front());
            for (const auto& [k, first] : with_grid) {
                k->setArg(first + a, starts_buffers[a]);
                k->setArg(first + 3 + a, static_cast<cl_int>(out.axes[a].count()));
                k->setArg(first + 6 + a, static_cast<cl_float>(raw_span > 0 ? out.axes[a].count() / raw_span : 0.0));
            }
        }
        for (const auto& [k, first] : with_grid) {
            k->setArg(first - 1, static_cast<cl_uint>(length));
            k->setArg(first + 9, static_cast<cl_uint>(out.bricks[0]));
            k->setArg(first + 10, static_cast<cl_uint>(out.bricks[1]));
            k->setArg(first + 11, index);
        }
        add.setArg(16, stats);
        add.setArg(17, deferred);
        add.setArg(18, deferred_count);
        mark.setArg(1, deferred);
        mark.setArg(16, new_bricks);
        mark.setArg(17, new_count);
        assign.setArg(0, new_bricks);
        assign.setArg(3, index);
        add_listed.setArg(1, deferred);
        add_listed.setArg(17, stats);

        // The points of the slice in `records` whose bricks were new: their bricks get slots (the
        // pool grows first when it must), then the points are added.
        auto add_deferred = [&](const cl::Buffer& records) {
            cl_uint listed = 0, fresh = 0;
            queue.enqueueReadBuffer(deferred_count, CL_TRUE, 0, sizeof listed, &listed);
            if (listed == 0) return;
            mark.setArg(0, records);
            mark.setArg(2, listed);
            queue.enqueueNDRangeKernel(mark, cl::NullRange, cl::NDRange((listed + 255) / 256 * 256), cl::NullRange);
            queue.enqueueReadBuffer(new_count, CL_TRUE, 0, sizeof fresh, &fresh);
            if (used + fresh > capacity) {
                // Grow the pool: a new buffer, the bricks so far copied over, the rest zero.
                std::uint64_t grown = std::max(capacity * 2, used + fresh);
                grown = std::min(grown, std::max(used + fresh, max_alloc / brick_bytes));
                const MemoryNeed need{fixed.device_bytes + (capacity + grown) * brick_bytes,
                                      fixed.host_bytes + (used + fresh) * DensityGrid::brick_cells * sizeof(CellSums),
                                      grown * brick_bytes};
                const std::string problem = exceeded(need, limits, "the pool of bricks");
                if (!problem.empty()) {
                    queue.finish();
                    const std::uint64_t limit =
                        std::min({max_alloc * 3, limits.global_memory, limits.max_memory ? limits.max_memory : UINT64_MAX});
                    const std::uint64_t fixed_bytes = fixed.device_bytes + fixed.host_bytes;
                    const std::uint64_t available = limit > fixed_bytes ? limit - fixed_bytes : 0;
                    pool_too_large(header, options, out.spec, problem, used + fresh, out.points_read, available);
                }
                cl::Buffer bigger(ctx, CL_MEM_READ_WRITE, grown * brick_bytes);
                if (used > 0) queue.enqueueCopyBuffer(pool, bigger, 0, 0, used * brick_bytes);
                queue.enqueueFillBuffer(bigger, cl_ulong{0}, used * brick_bytes, (grown - used) * brick_bytes);
                pool = bigger;
                capacity = grown;
                add.setArg(15, pool);
            }
            if (fresh > 0) {
                assign.setArg(1, fresh);
                assign.setArg(2, static_cast<cl_uint>(used));
                queue.enqueueNDRangeKernel(assign, cl::NullRange, cl::NDRange((fresh + 255) / 256 * 256), cl::NullRange);
                used += fresh;
            }
            add_listed.setArg(0, records);
            add_listed.setArg(2, listed);
            add_listed.setArg(16, pool);
            const std::size_t items = (listed + run_length - 1) / run_length;
            queue.enqueueNDRangeKernel(add_listed, cl::NullRange, cl::NDRange((items + 63) / 64 * 64), cl::NullRange);
            queue.enqueueFillBuffer(deferred_count, cl_uint{0}, 0, sizeof(cl_uint));
            queue.enqueueFillBuffer(new_count, cl_uint{0}, 0, sizeof(cl_uint));
        };

        // Double buffering: the host reads slice k + 1 into one mapped buffer while the device
        // adds slice k from the other. Maps go through a queue of their own, so that mapping one
        // buffer waits only for the kernels that used it, not for the slice still being added.
        // The points slice k could not add yet are added once slice k + 1 is read, before it.
        cl::CommandQueue transfers(ctx, dev.device);
        add.setArg(15, pool);
        std::array<cl::Buffer, slots> uploads;
        std::array<std::vector<cl::Event>, slots> done; // the last kernels that read each buffer
        for (std::size_t s = 0; s < slots; ++s)
            uploads[s] = cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_ALLOC_HOST_PTR, slice_bytes);
        for (std::uint64_t k = 0;; ++k) {
            const std::size_t s = k % slots;
            auto* mapped = static_cast<std::byte*>(
                transfers.enqueueMapBuffer(uploads[s], CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, slice_bytes, &done[s]));
            std::size_t n = 0;
            try {
                n = reader.read_records({mapped, slice_bytes});
            } catch (...) {
                transfers.enqueueUnmapMemObject(uploads[s], mapped);
                transfers.finish();
                queue.finish();
                throw;
            }
            std::vector<cl::Event> unmapped(1);
            transfers.enqueueUnmapMemObject(uploads[s], mapped, nullptr, &unmapped[0]);
            if (k > 0) {
                const std::size_t previous = (k - 1) % slots;
                add_deferred(uploads[previous]);
                done[previous].resize(1);
                queue.enqueueMarkerWithWaitList(nullptr, &done[previous][0]);
            }
            if (n == 0) break;
            out.points_read += n;
            if (options.on_slice) options.on_slice(out.points_read);
            add.setArg(0, uploads[s]);
            add.setArg(1, static_cast<cl_uint>(n));
            const std::size_t items = (n + run_length - 1) / run_length;
            queue.enqueueNDRangeKernel(add, cl::NullRange, cl::NDRange((items + 63) / 64 * 64), cl::NullRange, &unmapped);
            queue.flush();
        }
        queue.finish();

        cl_uint stat_words[4] = {};
        queue.enqueueReadBuffer(stats, CL_TRUE, 0, sizeof stat_words, stat_words);
        out.points_outside = stat_words[0] | (std::uint64_t{stat_words[1]} << 32);
        out.color_max_word = stat_words[2];

        // The bricks in ascending order of position, whatever order the device met them in.
        out.brick_index.resize(bricks);
        queue.enqueueReadBuffer(index, CL_TRUE, 0, bricks * 4, out.brick_index.data());
        std::vector<std::uint64_t> position_of_slot(used);
        for (std::uint64_t b = 0; b < bricks; ++b) {
            std::uint32_t& at = out.brick_index[b];
            if (at == 0) continue;
            position_of_slot[at - 1] = out.brick_keys.size();
            out.brick_keys.push_back(b);
            at = static_cast<std::uint32_t>(out.brick_keys.size());
        }
        // Read the pool back in blocks, each brick straight to its place.
        out.cells.resize(used * DensityGrid::brick_cells);
        const std::uint64_t words = cell_words(color);
        const std::uint64_t block_bricks = std::max<std::uint64_t>(1, (16ull << 20) / brick_bytes);
        std::vector<cl_ulong> block(block_bricks * DensityGrid::brick_cells * words);
        for (std::uint64_t first = 0; first < used; first += block_bricks) {
            const std::uint64_t n = std::min(block_bricks, used - first);
            queue.enqueueReadBuffer(pool, CL_TRUE, first * brick_bytes, n * brick_bytes, block.data());
            for (std::uint64_t s = 0; s < n; ++s) {
                CellSums* dst = &out.cells[position_of_slot[first + s] * DensityGrid::brick_cells];
                const cl_ulong* src = &block[s * DensityGrid::brick_cells * words];
                for (std::int64_t c = 0; c < DensityGrid::brick_cells; ++c, src += words) {
                    dst[c].count = src[0];
                    dst[c].position = {src[1], src[2], src[3]};
                    if (color) dst[c].color = {src[4], src[5], src[6]};
                }
            }
        }
    } catch (const cl::Error& e) {
        throw_device_error(e, "accumulating the grid on " + dev.info.name);
    }
    return out;
}

} // namespace lasmesh
