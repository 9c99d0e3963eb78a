// accumulate_density: streams raw records to the device in double-buffered slices and runs
// kernels/accumulate.cl over each; the host only reads and uploads.
#include "lasmesh/grid/density_grid.hpp"

#include "kernel_sources.hpp"
#include "lasmesh/error.hpp"
#include "opencl_device.hpp"

#include <algorithm>
#include <cstdio>

namespace lasmesh {

namespace {

// Measured on PoCL (docs/benchmarks.md): 4-16 MiB slices stay in cache and beat 64 MiB ones.
constexpr std::uint64_t default_slice_bytes = 16ull << 20;
constexpr std::size_t slots = 2; // one slice uploading or computing while the next is read

std::string mib(std::uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", bytes / 1048576.0);
    return text;
}

std::string dims_text(const GridSpec& g) {
    return std::to_string(g.dims[0]) + "x" + std::to_string(g.dims[1]) + "x" + std::to_string(g.dims[2]);
}

struct Limits {
    std::uint64_t global_memory, max_alloc, max_memory;
};

// Empty when the grid fits; otherwise what it exceeds.
std::string exceeded(const MemoryNeed& need, const Limits& limits) {
    if (need.largest_buffer > limits.max_alloc)
        return "the grid buffer needs " + mib(need.largest_buffer) + ", more than the device's largest allocation (" +
               mib(limits.max_alloc) + ")";
    if (need.device_bytes > limits.global_memory)
        return "it needs " + mib(need.device_bytes) + " of device memory, more than the device has (" +
               mib(limits.global_memory) + ")";
    if (limits.max_memory && need.device_bytes + need.host_bytes > limits.max_memory)
        return "it needs " + mib(need.device_bytes + need.host_bytes) + " on host and device together, more than --max-memory (" +
               mib(limits.max_memory) + ")";
    return {};
}

void check_memory(const LasHeader& header, const AccumulateOptions& options, const GridSpec& grid, std::uint64_t slice_bytes,
                  const Limits& limits) {
    const bool color = has_color(header);
    const std::string problem = exceeded(memory_need(grid, color, slice_bytes), limits);
    if (problem.empty()) return;
    // The largest N along the longest axis that fits, found by bisection (memory grows with N).
    std::uint32_t lo = 0, hi = std::max({grid.dims[0], grid.dims[1], grid.dims[2]});
    while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo + 1) / 2;
        AccumulateOptions trial = options;
        trial.grid = GridRequest{GridRequest::Kind::longest_axis, {mid, 0, 0}, 0};
        if (exceeded(memory_need(grid_for(header, trial), color, slice_bytes), limits).empty())
            lo = mid;
        else
            hi = mid - 1;
    }
    throw Error(ErrorKind::usage, "the grid " + dims_text(grid) + " (" + std::to_string(grid.cell_count()) +
                                      " cells) does not fit: " + problem +
                                      (lo > 0 ? "; --grid " + std::to_string(lo) + " would fit" : ""));
}

std::uint64_t join64(const cl_uint* pair) { return pair[0] | (std::uint64_t{pair[1]} << 32); }

} // namespace

Rgb8 DensityGrid::mean_color(std::uint64_t cell) const {
    const std::uint64_t n = count[cell];
    if (n == 0 || !has_color()) return {0, 0, 0};
    // Rounded integer division; 128-bit so no count or sum can overflow.
    const unsigned __int128 divisor = static_cast<unsigned __int128>(n) * (color_is_16bit() ? 257 : 1);
    auto mean = [&](std::uint64_t sum) {
        return static_cast<std::uint8_t>((2 * static_cast<unsigned __int128>(sum) + divisor) / (2 * divisor));
    };
    return {mean(red[cell]), mean(green[cell]), mean(blue[cell])};
}

MemoryNeed memory_need(const GridSpec& grid, bool has_color, std::uint64_t slice_bytes) {
    MemoryNeed need;
    const std::uint64_t grid_bytes = grid.cell_count() * 8 * (has_color ? 4 : 1);
    need.largest_buffer = grid_bytes;
    need.device_bytes = grid_bytes + slots * slice_bytes;
    // The per-channel grid the device's is read back into (a 16 MiB block at a time), plus the
    // staging slices.
    need.host_bytes = grid_bytes + (16ull << 20) + slots * slice_bytes;
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
    const std::uint64_t max_alloc = options.max_alloc ? std::min(options.max_alloc, dev.info.max_alloc) : dev.info.max_alloc;
    const std::uint64_t slice_limit = std::min(options.slice_bytes ? options.slice_bytes : default_slice_bytes, max_alloc);
    // No larger than the records still to come: a small file needs no 16 MiB slices.
    const std::size_t slice_records = static_cast<std::size_t>(
        std::clamp<std::uint64_t>(std::min<std::uint64_t>(slice_limit / length, reader.records_left()), 1, 1u << 30));
    const std::size_t slice_bytes = slice_records * length;
    check_memory(header, options, out.spec, slice_bytes, {dev.info.global_memory, max_alloc, options.max_memory});

    const std::uint64_t cells = out.spec.cell_count();
    std::array<AxisCells, 3> axes;
    for (int a = 0; a < 3; ++a) axes[a] = axis_cells(out.spec, a, header.scale[a], header.offset[a]);

    try {
        cl::Context& ctx = dev.context;
        cl::CommandQueue& queue = dev.queue;
        std::string defines = color ? "-D RGB_OFFSET=" + std::to_string(rgb_offset(header.point_format)) : "";
        cl::Program program = build_program(dev, "accumulate.cl", kernels::accumulate, defines);
        cl::Kernel kernel(program, "accumulate");

        // The grid: per cell 64-bit counters (count, then red, green, blue sums when there is
        // colour), each as low and high 32-bit words, zeroed on the device.
        const std::uint64_t counters = color ? 4 : 1;
        const std::uint64_t grid_bytes = cells * counters * 8;
        cl::Buffer grid(ctx, CL_MEM_READ_WRITE, grid_bytes);
        queue.enqueueFillBuffer(grid, cl_uint{0}, 0, grid_bytes);
        cl::Buffer stats(ctx, CL_MEM_READ_WRITE, 4 * sizeof(cl_uint));
        queue.enqueueFillBuffer(stats, cl_uint{0}, 0, 4 * sizeof(cl_uint));

        kernel.setArg(2, static_cast<cl_uint>(length));
        std::array<cl::Buffer, 3> starts_buffers; // kernel arguments do not keep buffers alive
        for (int a = 0; a < 3; ++a) {
            std::vector<cl_long> starts(axes[a].starts.begin(), axes[a].starts.end());
            starts_buffers[a] = cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, starts.size() * sizeof(cl_long),
                                           starts.data());
            kernel.setArg(3 + a, starts_buffers[a]);
            kernel.setArg(6 + a, static_cast<cl_int>(axes[a].count()));
            const double raw_span = static_cast<double>(starts.back() - starts.front());
            kernel.setArg(9 + a, static_cast<cl_float>(raw_span > 0 ? axes[a].count() / raw_span : 0.0));
        }
        kernel.setArg(12, grid);
        kernel.setArg(13, stats);

        // Double buffering: while the device works on slice k, the host reads slice k + 1. A
        // staging buffer is refilled only after its upload has completed.
        std::array<std::vector<std::byte>, slots> staging;
        std::array<cl::Buffer, slots> uploads;
        std::array<cl::Event, slots> uploaded;
        for (std::size_t s = 0; s < slots; ++s) {
            staging[s].resize(slice_bytes);
            uploads[s] = cl::Buffer(ctx, CL_MEM_READ_ONLY, slice_bytes);
        }
        for (std::uint64_t k = 0;; ++k) {
            const std::size_t s = k % slots;
            if (uploaded[s]()) uploaded[s].wait();
            const std::size_t n = reader.read_records(staging[s]);
            if (n == 0) break;
            out.points_read += n;
            if (options.on_slice) options.on_slice(out.points_read);
            queue.enqueueWriteBuffer(uploads[s], CL_FALSE, 0, n * length, staging[s].data(), nullptr, &uploaded[s]);
            kernel.setArg(0, uploads[s]);
            kernel.setArg(1, static_cast<cl_uint>(n));
            const std::size_t global = (n + 255) / 256 * 256;
            queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(global), cl::NullRange);
            queue.flush();
        }

        cl_uint stat_words[4] = {};
        queue.enqueueReadBuffer(stats, CL_TRUE, 0, sizeof stat_words, stat_words);
        out.points_outside = join64(stat_words);
        out.color_max_word = stat_words[2];
        // Read back in blocks and split the interleaved counters as they come, so the host never
        // holds a second whole copy of the grid (with PoCL the device buffer is host memory too).
        out.count.resize(cells);
        if (color) out.red.resize(cells), out.green.resize(cells), out.blue.resize(cells);
        const std::uint64_t block_cells = std::max<std::uint64_t>(1, (16ull << 20) / (counters * 8));
        std::vector<std::uint64_t> block(block_cells * counters);
        for (std::uint64_t first = 0; first < cells; first += block_cells) {
            const std::uint64_t n = std::min(block_cells, cells - first);
            queue.enqueueReadBuffer(grid, CL_TRUE, first * counters * 8, n * counters * 8, block.data());
            for (std::uint64_t c = 0; c < n; ++c) {
                out.count[first + c] = block[c * counters];
                if (!color) continue;
                out.red[first + c] = block[c * 4 + 1];
                out.green[first + c] = block[c * 4 + 2];
                out.blue[first + c] = block[c * 4 + 3];
            }
        }
    } catch (const cl::Error& e) {
        throw_device_error(e, "accumulating the grid on " + dev.info.name);
    }
    return out;
}

} // namespace lasmesh
