// Where PoCL (the CPU OpenCL driver) caches compiled kernels (see kernel_cache.cpp).
#pragma once

namespace lasmesh::cli {

// Call in main() before any OpenCL call: points POCL_CACHE_DIR at lasmesh's own cache folder
// unless the user set it.
void use_own_kernel_cache();

} // namespace lasmesh::cli
