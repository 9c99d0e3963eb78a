// SPDX-License-Identifier: Apache-2.0
// accumulate_cells: streams raw records to the device in double-buffered slices and runs
// kernels/accumulate.cl over each; the host reads records straight into the device's slice
// buffers (mapped, so a device that shares host memory copies nothing), adds a chunk to the pool
// of bricks when a slice's new bricks would not fit, and reads the pool back in brick order.
// The steps, in the order DeviceAccumulation::run takes them: plan the slices, build the kernels, make
// the buffers, then per slice upload and add (new bricks deferred: grow the pool, give them
// slots, add their points), then read the totals and the pool back.
#include "grid/auto_grid.hpp"
#include "grid/cell_sums.hpp"
#include "read/input_stream.hpp"
#include "read/survey.hpp"

#include "brick_pool.hpp"
#include "host_memory.hpp"
#include "kernel_sources.hpp"
#include "lasmesh/error.hpp"
#include "memory_guard.hpp"
#include "opencl_device.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace lasmesh {

namespace {

// On PoCL, slices of 4-16 MiB stay in the CPU's caches while the device sums them; 64 MiB ones were slower.
constexpr std::uint64_t default_slice_bytes = 16ull << 20;
constexpr std::size_t slots = slice_buffers;
// Records one work-item sums before it flushes: long enough to merge the runs of a scan in
// acquisition order, short enough to keep every core busy on a small slice.
constexpr unsigned run_length = 32;
// The bits of each of the three position lanes of a cell's first 64-bit word (kernels/accumulate.cl).
constexpr unsigned position_bits = 21;

// The widest cell of the grid, in raw units: it bounds what a point adds to a position sum (and
// its square what it adds to a moment).
std::uint64_t widest_cell(const std::array<AxisCells, 3>& axes) {
    std::int64_t widest = 0;
    for (const AxisCells& axis : axes)
        for (std::size_t i = 0; i + 1 < axis.starts.size(); ++i)
            widest = std::max(widest, axis.starts[i + 1] - axis.starts[i]);
    return static_cast<std::uint64_t>(widest);
}

// The moments' lanes a 64-bit word of the pool (kernels/accumulate.cl): three of 21 bits while
// a lane takes at least 128 points of the widest cell's largest moment before it wraps (cells up
// to 12.8 cm at a millimetre scale), else two of 32 bits; wrapping lanes list carries.
unsigned moment_lanes(const std::array<AxisCells, 3>& axes) {
    const std::uint64_t w = widest_cell(axes);
    return w <= 128 ? 3 : 2;
}

// The pool keeps the low 32 bits of the count and colour sums, 21 of the position sums, and 21
// or 32 of the moments; an add that carries past them lists what they did not keep
// (kernels/accumulate.cl). Listed between two reads by the host: at most one entry per sum a run
// flushes, and at most two kernels' worth of runs (`points_between_reads` points). Over the whole
// run: a sum of b bits lists once per add of 2^b or more and once per wrap (each at most its total
// over 2^b), and the sum above it in its 64-bit word once more per wrap (the add spills into it):
// at most 3 T / 2^b entries, T the totals of the sums, at most `points` times the largest a point
// adds to them. The list needs the smaller of the two.
std::uint64_t carry_capacity(std::uint64_t points, std::uint64_t points_between_reads,
                             const std::array<AxisCells, 3>& axes, unsigned moment_lanes, bool color) {
    const auto w = static_cast<unsigned __int128>(widest_cell(axes));
    const unsigned __int128 per_word = 1 + (color ? 3 * 65535 : 0), per_lane = 3 * w, per_moment = 6 * w * w;
    const unsigned __int128 over_run = (3 * per_word * points >> 32) + (3 * per_lane * points >> position_bits) +
                                       (3 * per_moment * points >> (64 / moment_lanes)) + 3;
    const std::uint64_t between_reads = points_between_reads * cell_sums(color);
    return 1 + static_cast<std::uint64_t>(std::min<unsigned __int128>(over_run, between_reads));
}

// One listed carry: the 64-bit sum `key` (cell_sums) gets `delta` added (modulo 2^64).
struct Carry {
    std::uint64_t key = 0, delta = 0;
    bool operator<(const Carry& o) const { return key < o.key; }
};

// One accumulation: the device's buffers and kernels, the host's view of the pool, and the grid
// being filled. Each step is a member function; run() calls them in order.
class DeviceAccumulation {
  public:
    DeviceAccumulation(SurveyReader& reader, ComputeDevice& device, const AccumulateOptions& options)
        : reader_(reader), header_(reader.header()), dev_(device.impl()), options_(options),
          length_(header_.point_record_length), color_(has_color(header_)) {}

    CellGrid run() {
        try {
            plan_slices();
            build_kernels();
            make_buffers();
            add_slices();
            read_totals();
            read_back();
        } catch (const cl::Error& e) {
            throw_device_error(e, "accumulating the grid on " + dev_.info.name);
        }
        return std::move(out_);
    }

  private:
    // The grid, the slice size (no larger than the records still to come: a small file needs no
    // 16 MiB slices), the memory the fixed buffers take, and the pool's layout.
    void plan_slices() {
        out_.spec = grid_for(header_, options_);
        out_.color = color_;
        out_.moments = true;
        out_.scale = header_.scale;
        out_.offset = header_.offset;
        out_.bricks = brick_dims(out_.spec);
        max_alloc_ = options_.max_alloc ? std::min(options_.max_alloc, dev_.info.max_alloc) : dev_.info.max_alloc;
        const std::uint64_t slice_limit =
            std::min(options_.slice_bytes ? options_.slice_bytes : default_slice_bytes, max_alloc_);
        slice_records_ = static_cast<std::size_t>(std::clamp<std::uint64_t>(
            std::min<std::uint64_t>(slice_limit / length_, reader_.records_left()), 1, 1u << 30));
        slice_bytes_ = slice_records_ * length_;
        limits_ = {dev_.info.global_memory, max_alloc_, options_.max_memory,
                   options_.max_memory ? options_.memory_in_use : 0};
        check_index_memory(header_, options_, out_.spec, slice_bytes_, limits_);
        for (int a = 0; a < 3; ++a) {
            out_.axes[a] =
                options_.axes ? (*options_.axes)[a] : axis_cells(out_.spec, a, header_.scale[a], header_.offset[a]);
            if (out_.axes[a].starts.size() != std::size_t{out_.spec.dims[a]} + 1)
                throw std::logic_error("accumulate_cells: the cell starts given do not match the grid");
        }
        brick_bytes_ = brick_device_bytes(color_);
        moment_lanes_ = moment_lanes(out_.axes);
        carry_slots_ = carry_capacity(reader_.records_left(), 2 * slice_records_, out_.axes, moment_lanes_, color_);
        fixed_ = memory_need(out_.spec, slice_bytes_);
        fixed_.device_bytes += carry_slots_ * 2 * sizeof(std::uint64_t);
        layout_ = pool_layout(std::max<std::uint64_t>(1, max_alloc_ / brick_bytes_));
        // On a CPU device the large buffers are host memory we map ourselves, zeroed and in large
        // pages: a refused allocation is then std::bad_alloc here (PoCL aborts when its own lazy
        // allocation fails), and nothing needs clearing.
        host_device_ = dev_.info.type == "CPU" && !options_.device_memory;
    }

    // A device buffer, or on a CPU device one over host memory we map into `memory` (zeroed).
    cl::Buffer large_buffer(HostMemory& memory, std::uint64_t bytes) {
        if (!host_device_) return cl::Buffer(dev_.context, CL_MEM_READ_WRITE, bytes);
        memory = HostMemory(bytes);
        return cl::Buffer(dev_.context, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, bytes, memory.data());
    }

    void build_kernels() {
        std::string defines = "-D BRICK_BITS=" + std::to_string(CellGrid::brick_bits) +
                              " -D RUN=" + std::to_string(run_length) +
                              " -D FIRST_BITS=" + std::to_string(layout_.first_bits) +
                              " -D DOUBLINGS=" + std::to_string(layout_.doublings);
        // PoCL compiles kernels with clang, whose prefetch builtin is a real one (OpenCL's is not).
        if (host_device_ && dev_.info.platform.find("Portable Computing Language") != std::string::npos)
            defines += " -D CPU_PREFETCH";
        if (color_) defines += " -D RGB_OFFSET=" + std::to_string(rgb_offset(header_.point_format));
        defines +=
            " -D POSITION_BITS=" + std::to_string(position_bits) + " -D MOMENT_LANES=" + std::to_string(moment_lanes_);
        // The cells' words are added two at a time with 64-bit atomics (kernels/accumulate.cl).
        if (dev_.device.getInfo<CL_DEVICE_EXTENSIONS>().find("cl_khr_int64_base_atomics") == std::string::npos)
            throw Error(ErrorKind::device,
                        dev_.info.name + " has no 64-bit atomics (cl_khr_int64_base_atomics), which "
                                         "accumulating the grid needs: choose another device",
                        "device");
        cl::Program program = build_program(dev_, "accumulate.cl", kernels::accumulate, defines);
        add_ = cl::Kernel(program, "accumulate");
        mark_ = cl::Kernel(program, "mark_bricks");
        assign_ = cl::Kernel(program, "assign_bricks");
        add_listed_ = cl::Kernel(program, "accumulate_listed");
        // Work-group sizes chosen here, not by the device: PoCL compiles a kernel once for each
        // work-group size it meets (0.1-0.4 s a run), and left to choose it took one from the
        // factors of each launch's size, so the last slice of a file of a new length often cost a
        // compile. Launches are whole multiples of 64 (accumulating) or 256 (bricks) work-items.
        auto group_size = [&](const cl::Kernel& kernel, std::size_t preferred) {
            const auto most = kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(dev_.device);
            while (preferred > most && preferred > 1) preferred /= 2; // still divides the launch
            return cl::NDRange(preferred);
        };
        add_group_ = group_size(add_, 64);
        add_listed_group_ = group_size(add_listed_, 64);
        mark_group_ = group_size(mark_, 256);
        assign_group_ = group_size(assign_, 256);
    }

    // The brick index, the lists of deferred points and new bricks, the counters, carries and
    // stats, each set as the kernels' arguments.
    void make_buffers() {
        cl::Context& ctx = dev_.context;
        cl::CommandQueue& queue = dev_.queue;
        const std::uint64_t bricks = brick_count(out_.spec);
        index_ = large_buffer(index_memory_, bricks * 4);
        if (!host_device_) queue.enqueueFillBuffer(index_, cl_uint{0}, 0, bricks * 4);
        // The points of a slice whose bricks were new, and the bricks they claimed: each at most
        // one per record.
        deferred_ = large_buffer(deferred_memory_, slice_records_ * 4);
        new_bricks_ = large_buffer(new_bricks_memory_, slice_records_ * 4);
        // Points deferred, bricks new, carries listed.
        counters_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, 3 * sizeof(cl_uint));
        queue.enqueueFillBuffer(counters_, cl_uint{0}, 0, 3 * sizeof(cl_uint));
        carry_list_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, carry_slots_ * 2 * sizeof(cl_ulong));
        stats_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, 4 * sizeof(cl_uint));
        queue.enqueueFillBuffer(stats_, cl_uint{0}, 0, 4 * sizeof(cl_uint));

        // The grid's arguments (starts, cell counts, cells per raw unit, bricks along x and y) and
        // the index come at the same place in each kernel, after `first` others.
        const std::array<std::pair<cl::Kernel*, int>, 3> with_grid{{{&add_, 3}, {&mark_, 4}, {&add_listed_, 4}}};
        for (int a = 0; a < 3; ++a) {
            std::vector<cl_long> starts(out_.axes[a].starts.begin(), out_.axes[a].starts.end());
            starts_buffers_[a] = cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                            starts.size() * sizeof(cl_long), starts.data());
            const double raw_span = static_cast<double>(starts.back() - starts.front());
            for (const auto& [k, first] : with_grid) {
                k->setArg(first + a, starts_buffers_[a]);
                k->setArg(first + 3 + a, static_cast<cl_int>(out_.axes[a].count()));
                k->setArg(first + 6 + a, static_cast<cl_float>(raw_span > 0 ? out_.axes[a].count() / raw_span : 0.0));
            }
        }
        for (const auto& [k, first] : with_grid) {
            k->setArg(first - 1, static_cast<cl_uint>(length_));
            k->setArg(first + 9, static_cast<cl_uint>(out_.bricks[0]));
            k->setArg(first + 10, static_cast<cl_uint>(out_.bricks[1]));
            k->setArg(first + 11, index_);
        }
        // Then the pool's chunks (null until they exist), the carries, stats, the list of deferred
        // points and the counters.
        set_chunk_arguments_null();
        for (const auto& [k, first] :
             {std::pair{&add_, pool_arg_add + chunk_args}, std::pair{&add_listed_, pool_arg_listed + chunk_args}}) {
            k->setArg(first, carry_list_);
            k->setArg(first + 1, static_cast<cl_uint>(carry_slots_));
            k->setArg(first + 2, stats_);
        }
        add_.setArg(pool_arg_add + chunk_args + 3, deferred_);
        add_.setArg(pool_arg_add + chunk_args + 4, counters_);
        add_listed_.setArg(pool_arg_listed + chunk_args + 3, counters_);
        mark_.setArg(1, deferred_);
        mark_.setArg(16, new_bricks_);
        mark_.setArg(17, counters_);
        assign_.setArg(0, new_bricks_);
        assign_.setArg(3, index_);
        add_listed_.setArg(1, deferred_);
    }

    void set_chunk_arguments_null() {
        for (int c = 0; c < chunk_args; ++c) {
            add_.setArg(pool_arg_add + c, cl::Buffer());
            add_listed_.setArg(pool_arg_listed + c, cl::Buffer());
        }
    }

    // Double buffering: the host reads slice k + 1 into one mapped buffer while the device adds
    // slice k from the other. Maps go through a queue of their own, so that mapping one buffer
    // waits only for the kernels that used it, not for the slice still being added. The points
    // slice k could not add yet are added once slice k + 1 is read, before it.
    void add_slices() {
        cl::CommandQueue& queue = dev_.queue;
        cl::CommandQueue transfers(dev_.context, dev_.device);
        std::array<HostMemory, slots> upload_memory;    // a CPU device's slices: our memory, in large pages
        std::array<cl::Buffer, slots> uploads;          // (released first: declared after their memory)
        std::array<std::vector<cl::Event>, slots> done; // the last kernels that read each buffer
        for (std::size_t s = 0; s < slots; ++s)
            uploads[s] = host_device_
                             ? large_buffer(upload_memory[s], slice_bytes_)
                             : cl::Buffer(dev_.context, CL_MEM_READ_ONLY | CL_MEM_ALLOC_HOST_PTR, slice_bytes_);
        for (std::uint64_t k = 0;; ++k) {
            const std::size_t s = k % slots;
            auto* mapped = static_cast<std::byte*>(transfers.enqueueMapBuffer(
                uploads[s], CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, slice_bytes_, &done[s]));
            std::size_t n = 0;
            try {
                n = reader_.read_records({mapped, slice_bytes_});
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
            out_.points_read += n;
            if (options_.on_slice) options_.on_slice(out_.points_read);
            add_.setArg(0, uploads[s]);
            add_.setArg(1, static_cast<cl_uint>(n));
            const std::size_t items = (n + run_length - 1) / run_length;
            queue.enqueueNDRangeKernel(add_, cl::NullRange, cl::NDRange((items + 63) / 64 * 64), add_group_, &unmapped);
            queue.flush();
        }
        queue.finish();
    }

    // The points of the slice in `records` whose bricks were new: their bricks get slots (the
    // pool grows first when it must), then the points are added.
    void add_deferred(const cl::Buffer& records) {
        cl::CommandQueue& queue = dev_.queue;
        cl_uint count[3] = {};
        queue.enqueueReadBuffer(counters_, CL_TRUE, 0, sizeof count, count);
        take_carries(count[2]);
        const cl_uint listed = count[0];
        if (listed == 0) return;
        mark_.setArg(0, records);
        mark_.setArg(2, listed);
        queue.enqueueNDRangeKernel(mark_, cl::NullRange, cl::NDRange((listed + 255) / 256 * 256), mark_group_);
        cl_uint fresh = 0;
        queue.enqueueReadBuffer(counters_, CL_TRUE, sizeof(cl_uint), sizeof fresh, &fresh);
        grow_pool(fresh);
        if (fresh > 0) give_slots(fresh);
        add_listed_.setArg(0, records);
        add_listed_.setArg(2, listed);
        const std::size_t items = (listed + run_length - 1) / run_length;
        queue.enqueueNDRangeKernel(add_listed_, cl::NullRange, cl::NDRange((items + 63) / 64 * 64), add_listed_group_);
        queue.enqueueFillBuffer(counters_, cl_uint{0}, 0, 2 * sizeof(cl_uint));
    }

    // Adds chunks to the pool until `fresh` more bricks fit; nothing moves. Refuses, with a grid
    // that would fit, when the next chunk would pass the device's or the user's memory.
    void grow_pool(std::uint64_t fresh) {
        while (used_ + fresh > layout_.chunk_start(static_cast<unsigned>(chunks_.size()))) {
            const auto c = static_cast<unsigned>(chunks_.size());
            const std::uint64_t capacity = layout_.chunk_start(c + 1);
            // A device's chunks take their whole size; a CPU device's take memory only for the
            // bricks in use, and the host's copy replaces them chunk by chunk when read back. A
            // device's pool is read back into the host's copy once more.
            const std::uint64_t device_pool = host_device_ ? (used_ + fresh) * brick_bytes_ : capacity * brick_bytes_;
            const std::uint64_t host_copy =
                host_device_ ? 0 : (used_ + fresh) * CellGrid::brick_cells * sizeof(CellSums);
            const MemoryNeed need{fixed_.device_bytes - first_chunk_bytes(out_.spec) + device_pool,
                                  fixed_.host_bytes + host_copy, layout_.chunk_bricks(c) * brick_bytes_};
            std::string problem = c == PoolLayout::max_chunks
                                      ? "it needs more than " + std::to_string(PoolLayout::max_chunks) +
                                            " buffers of up to " + mib(layout_.chunk_bricks(c) * brick_bytes_) +
                                            " (the device's largest allocation)"
                                      : exceeded(need, limits_, "the pool of bricks");
            if (!problem.empty()) {
                dev_.queue.finish();
                const std::uint64_t limit =
                    std::min({layout_.chunk_start(PoolLayout::max_chunks) * brick_bytes_, limits_.global_memory,
                              limits_.max_memory ? limits_.max_memory : UINT64_MAX});
                const std::uint64_t fixed_bytes = fixed_.device_bytes + fixed_.host_bytes + limits_.in_use;
                const std::uint64_t available = limit > fixed_bytes ? limit - fixed_bytes : 0;
                // Per byte of bricks in use: on a device up to twice in doubling chunks, and the
                // host's copy of the occupied cells about once more; on a CPU device about once;
                // and meshing the grid takes about 1.5 times it again (3/4 when measured on the
                // deck with 64-bit cells, whose pool was twice the size).
                pool_too_large(header_, out_.spec, problem, used_ + fresh, out_.points_read, available,
                               host_device_ ? 2.5 : 4.5);
            }
            const std::uint64_t chunk_bytes = layout_.chunk_bricks(c) * brick_bytes_;
            chunk_memory_.emplace_back();
            chunks_.push_back(large_buffer(chunk_memory_.back(), chunk_bytes));
            add_.setArg(pool_arg_add + static_cast<int>(c), chunks_.back());
            add_listed_.setArg(pool_arg_listed + static_cast<int>(c), chunks_.back());
        }
    }

    // The `fresh` bricks mark_bricks listed get the next slots of the pool, cleared.
    void give_slots(std::uint64_t fresh) {
        cl::CommandQueue& queue = dev_.queue;
        // Which brick each new slot holds, in the order assign_bricks gives them slots: the host
        // never reads the whole index back (its size is the grid's volume).
        slot_keys_.resize(used_ + fresh);
        std::vector<cl_uint> keys(fresh);
        queue.enqueueReadBuffer(new_bricks_, CL_TRUE, 0, fresh * sizeof(cl_uint), keys.data());
        std::copy(keys.begin(), keys.end(), slot_keys_.begin() + static_cast<std::ptrdiff_t>(used_));
        // The new bricks start at zero: host memory is mapped zeroed; device chunks are not
        // cleared when made, only as they are used.
        for (unsigned c = 0; !host_device_ && c < chunks_.size(); ++c) {
            const std::uint64_t first = std::max(used_, layout_.chunk_start(c));
            const std::uint64_t end = std::min(used_ + fresh, layout_.chunk_start(c + 1));
            if (first < end)
                queue.enqueueFillBuffer(chunks_[c], cl_ulong{0}, (first - layout_.chunk_start(c)) * brick_bytes_,
                                        (end - first) * brick_bytes_);
        }
        assign_.setArg(1, static_cast<cl_uint>(fresh));
        assign_.setArg(2, static_cast<cl_uint>(used_));
        queue.enqueueNDRangeKernel(assign_, cl::NullRange, cl::NDRange((fresh + 255) / 256 * 256), assign_group_);
        used_ += fresh;
    }

    // Every kernel so far has finished: takes the carries they listed, and empties the list.
    void take_carries(cl_uint listed) {
        if (listed == 0) return;
        if (listed > carry_slots_)
            throw Error(ErrorKind::device, "the list of carries overflowed (" + std::to_string(listed) + " of " +
                                               std::to_string(carry_slots_) + "): the sums would be wrong");
        std::vector<cl_ulong> pairs(2 * std::size_t{listed});
        dev_.queue.enqueueReadBuffer(carry_list_, CL_TRUE, 0, pairs.size() * sizeof(cl_ulong), pairs.data());
        for (std::size_t i = 0; i < pairs.size(); i += 2) carries_.push_back({pairs[i], pairs[i + 1]});
        dev_.queue.enqueueFillBuffer(counters_, cl_uint{0}, 2 * sizeof(cl_uint), sizeof(cl_uint));
    }

    // The last carries, the points outside the grid and the largest colour word.
    void read_totals() {
        cl::CommandQueue& queue = dev_.queue;
        cl_uint carries_listed = 0;
        queue.enqueueReadBuffer(counters_, CL_TRUE, 2 * sizeof(cl_uint), sizeof carries_listed, &carries_listed);
        take_carries(carries_listed);
        std::sort(carries_.begin(), carries_.end());
        cl_uint stat_words[4] = {};
        queue.enqueueReadBuffer(stats_, CL_TRUE, 0, sizeof stat_words, stat_words);
        out_.points_outside = stat_words[0] | (std::uint64_t{stat_words[1]} << 32);
        out_.color_max_word = stat_words[2];
        // Colour fields that are 0 in every record hold no colour (a writer that had none): a
        // mesh "coloured" black would hide that, so the grid has no colour then.
        if (color_ && out_.color_max_word == 0) out_.color = false;
    }

    // The occupied bricks in ascending order of position, whatever order the device met them in;
    // the pool read back chunk by chunk in slot order, each chunk released once read, so the
    // device's copy shrinks while the host's grows. The host keeps only the cells that hold a
    // point, each brick's where the slot order puts it (CellGrid says how to find them), with the
    // carries added to their 64-bit sums.
    void read_back() {
        cl::CommandQueue& queue = dev_.queue;
        std::vector<std::uint64_t> slot_of_position(used_);
        for (std::uint64_t slot = 0; slot < used_; ++slot) slot_of_position[slot] = slot;
        std::sort(slot_of_position.begin(), slot_of_position.end(),
                  [&](std::uint64_t a, std::uint64_t b) { return slot_keys_[a] < slot_keys_[b]; });
        std::vector<std::uint64_t> position_of_slot(used_);
        out_.brick_keys.resize(used_);
        for (std::uint64_t b = 0; b < used_; ++b) {
            position_of_slot[slot_of_position[b]] = b;
            out_.brick_keys[b] = slot_keys_[slot_of_position[b]];
        }
        std::vector<std::uint32_t>().swap(slot_keys_);
        out_.index_bricks();
        set_chunk_arguments_null();
        out_.brick_masks.resize(used_);
        out_.brick_first.resize(used_);
        // Room for every cell of every brick, in address space only: pages are taken as written.
        out_.cells.reserve(used_ * CellGrid::brick_cells);
        advise_large_pages(out_.cells.data(), out_.cells.capacity() * sizeof(CellSums));
        const std::uint64_t words = cell_words(color_), sums = cell_sums(color_), moments = moment_word(color_);
        const unsigned lanes = moment_lanes_;
        // Lane i of `bits` bits of the 64-bit word at a cell's 32-bit word `word`.
        const auto lane = [](const cl_uint* cell, std::uint64_t word, unsigned i, unsigned bits) {
            const std::uint64_t both = cell[word] | std::uint64_t{cell[word + 1]} << 32;
            return both >> (bits * i) & ((std::uint64_t{1} << bits) - 1);
        };
        const std::uint64_t block_bricks = std::max<std::uint64_t>(1, (16ull << 20) / brick_bytes_);
        auto carry = carries_.begin();
        std::array<CellSums, CellGrid::brick_cells> brick{};
        for (unsigned c = 0; c < chunks_.size(); ++c) {
            const std::uint64_t start = layout_.chunk_start(c);
            const std::uint64_t in_chunk = used_ > start ? std::min(layout_.chunk_bricks(c), used_ - start) : 0;
            for (std::uint64_t first = 0; first < in_chunk; first += block_bricks) {
                const std::uint64_t n = std::min(block_bricks, in_chunk - first);
                // Mapped, not read: a CPU device's pool is host memory already, so nothing is copied
                // (a 16 MiB read buffer cost a memset and 4,096 page faults a run, however small the pool).
                const auto* block = static_cast<const cl_uint*>(
                    queue.enqueueMapBuffer(chunks_[c], CL_TRUE, CL_MAP_READ, first * brick_bytes_, n * brick_bytes_));
                for (std::uint64_t i = 0; i < n; ++i) {
                    const std::uint64_t slot = start + first + i;
                    const cl_uint* src = block + i * CellGrid::brick_cells * words;
                    for (std::size_t k = 0; k < brick.size(); ++k, src += words) {
                        for (unsigned a = 0; a < 3; ++a) brick[k].position[a] = lane(src, 0, a, position_bits);
                        brick[k].count = src[2];
                        if (color_) brick[k].color = {src[4], src[5], src[3]};
                        for (unsigned m = 0; m < 6; ++m)
                            brick[k].moments[m] = lane(src, moments + 2 * (m / lanes), m % lanes, 64 / lanes);
                    }
                    const std::uint64_t first_key = slot * CellGrid::brick_cells * sums;
                    for (; carry != carries_.end() && carry->key < first_key + CellGrid::brick_cells * sums; ++carry) {
                        CellSums& cell = brick[(carry->key - first_key) / sums];
                        const std::uint64_t which = (carry->key - first_key) % sums;
                        std::uint64_t& sum = which < 3           ? cell.position[which]
                                             : which == 3        ? cell.count
                                             : which >= sums - 6 ? cell.moments[which - (sums - 6)]
                                             : which == 4        ? cell.color[2]
                                                                 : cell.color[which - 5];
                        sum += carry->delta;
                    }
                    const std::uint64_t b = position_of_slot[slot];
                    out_.brick_first[b] = out_.cells.size();
                    out_.brick_masks[b] = out_.append_occupied(brick);
                }
                queue.enqueueUnmapMemObject(chunks_[c], const_cast<cl_uint*>(block));
                queue.finish();
                chunk_memory_[c].release(first * brick_bytes_, n * brick_bytes_);
            }
            chunks_[c] = cl::Buffer();
            chunk_memory_[c] = HostMemory();
        }
    }

    // Where the pool's chunks start among each kernel's arguments.
    static constexpr int pool_arg_add = 15, pool_arg_listed = 16, chunk_args = PoolLayout::max_chunks;

    SurveyReader& reader_;
    const LasHeader& header_;
    ComputeDevice::Impl& dev_;
    const AccumulateOptions& options_;
    const std::size_t length_; // bytes a record
    const bool color_;

    CellGrid out_;
    std::uint64_t max_alloc_ = 0;
    std::size_t slice_records_ = 0, slice_bytes_ = 0;
    MemoryLimits limits_{};
    std::uint64_t brick_bytes_ = 0, carry_slots_ = 0;
    MemoryNeed fixed_{};
    PoolLayout layout_{};
    bool host_device_ = false;
    unsigned moment_lanes_ = 2; // the moments' lanes a 64-bit word (moment_lanes)

    cl::Kernel add_, mark_, assign_, add_listed_;
    cl::NDRange add_group_, add_listed_group_, mark_group_, assign_group_;

    // Host memory first: the buffers over it are declared after it, so they are released first.
    HostMemory index_memory_, deferred_memory_, new_bricks_memory_;
    std::vector<HostMemory> chunk_memory_; // the pool's chunks
    cl::Buffer index_, deferred_, new_bricks_, counters_, carry_list_, stats_;
    std::array<cl::Buffer, 3> starts_buffers_; // kernel arguments do not keep buffers alive
    std::vector<cl::Buffer> chunks_;
    std::uint64_t used_ = 0;               // bricks in the pool
    std::vector<std::uint32_t> slot_keys_; // the brick in each slot of the pool
    std::vector<Carry> carries_;
};

} // namespace

// Accumulates into the grid `options` names exactly (a chosen request, or a given spec).
static CellGrid accumulate_into(SurveyReader& reader, ComputeDevice& device, const AccumulateOptions& options) {
    return DeviceAccumulation(reader, device, options).run();
}

CellGrid accumulate_cells(SurveyReader& reader, ComputeDevice& device, const AccumulateOptions& options) {
    const GridRequest& request = options.grid;
    if (options.spec || request.kind != GridRequest::Kind::automatic) return accumulate_into(reader, device, options);
    if (request.dims != std::array<std::uint32_t, 3>{0, 0, 0} || request.voxel != 0)
        throw Error(ErrorKind::usage, "the grid request gives cells or a cell edge but asks for an automatic grid: "
                                      "GridRequest::longest(N), cells(NX, NY, NZ) or cell_edge(E) set both");
    // The header's count and extents give a first grid; the counts in its cells a second look.
    const LasHeader& header = reader.header();
    const GridChoice choice =
        choose_grid(header.point_count, options.bounds.value_or(Bounds{header.min, header.max}), reader.name());
    AccumulateOptions chosen = options;
    chosen.grid = choice.request;
    CellGrid grid = accumulate_into(reader, device, chosen);
    finish_chosen_grid(grid, choice);
    return grid;
}

CellGrid accumulate_cells(LasReader& reader, ComputeDevice& device, const AccumulateOptions& options) {
    SurveyReader records(reader);
    return accumulate_cells(records, device, options);
}

} // namespace lasmesh
