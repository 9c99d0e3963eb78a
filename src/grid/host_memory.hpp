// SPDX-License-Identifier: Apache-2.0
// Internal: zeroed host memory in 2 MiB pages where the kernel allows it (Linux transparent huge
// pages, madvise). For a CPU OpenCL device the pool of bricks lives in host memory anyway; in
// large pages, random adds to a pool of a gigabyte miss the TLB far less, and the memory costs
// one page fault per 2 MiB instead of one per 4 KiB.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <new>
#include <utility>

#include <sys/mman.h>

namespace lasmesh {

// Asks for large pages for the 2 MiB-aligned part of [data, data + bytes) (advice only).
inline void advise_large_pages(void* data, std::size_t bytes) {
    constexpr std::uintptr_t large_page = 2u << 20;
    const auto begin = (reinterpret_cast<std::uintptr_t>(data) + large_page - 1) & ~(large_page - 1);
    const auto end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(large_page - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

class HostMemory {
  public:
    HostMemory() = default;
    explicit HostMemory(std::size_t bytes) {
        constexpr std::size_t large_page = 2u << 20;
        const std::size_t mapped = bytes + large_page;
        void* p = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) throw std::bad_alloc();
        // Keep a large-page-aligned part of the mapping; give back what lies before and after it.
        auto* start = static_cast<char*>(p);
        auto* aligned =
            reinterpret_cast<char*>((reinterpret_cast<std::uintptr_t>(start) + large_page - 1) & ~(large_page - 1));
        if (aligned > start) munmap(start, static_cast<std::size_t>(aligned - start));
        char* end = start + mapped;
        const std::size_t kept = (bytes + 4095) & ~std::size_t{4095};
        if (end > aligned + kept) munmap(aligned + kept, static_cast<std::size_t>(end - (aligned + kept)));
        madvise(aligned, kept, MADV_HUGEPAGE); // advice only: without it, ordinary pages
        data_ = aligned;
        bytes_ = kept;
    }
    HostMemory(HostMemory&& o) noexcept : data_(std::exchange(o.data_, nullptr)), bytes_(std::exchange(o.bytes_, 0)) {}
    HostMemory& operator=(HostMemory&& o) noexcept {
        std::swap(data_, o.data_);
        std::swap(bytes_, o.bytes_);
        return *this;
    }
    HostMemory(const HostMemory&) = delete;
    HostMemory& operator=(const HostMemory&) = delete;
    ~HostMemory() {
        if (data_) munmap(data_, bytes_);
    }
    void* data() const { return data_; }
    // Gives the whole pages inside [offset, offset + bytes) back to the system (they read as
    // zero afterwards): memory already copied elsewhere stops counting.
    void release(std::size_t offset, std::size_t bytes) {
        const std::size_t begin = (offset + 4095) & ~std::size_t{4095};
        const std::size_t end = std::min(offset + bytes, bytes_) & ~std::size_t{4095};
        if (data_ && end > begin) madvise(static_cast<char*>(data_) + begin, end - begin, MADV_DONTNEED);
    }

  private:
    void* data_ = nullptr;
    std::size_t bytes_ = 0;
};

} // namespace lasmesh
