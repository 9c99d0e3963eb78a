// SPDX-License-Identifier: Apache-2.0
// Where PoCL (the CPU OpenCL driver) caches compiled kernels (see kernel_cache.cpp).
#pragma once

#include <string>

namespace lasmesh::cli {

// Made in main() before any OpenCL call: points POCL_CACHE_DIR at lasmesh's own cache folder
// unless the user set it; where that folder cannot be written, at a temporary one of this run,
// removed when this is destroyed.
class KernelCache {
  public:
    KernelCache();
    ~KernelCache();
    KernelCache(const KernelCache&) = delete;
    KernelCache& operator=(const KernelCache&) = delete;

    // Why compiling the kernels would fail, or "" : a file size limit (ulimit -f) below what the
    // OpenCL compiler writes (LLVM then ends the process itself, with exit code 1).
    std::string problem() const;

  private:
    std::string temporary_; // the run's own folder, when the lasting one cannot be written
};

} // namespace lasmesh::cli
