// PoCL caches every compiled kernel under ~/.cache/pocl/kcache, shared with every other OpenCL
// program, and a write cut short (a full disk, `ulimit -f`) leaves empty files there that nobody
// knows to remove. lasmesh's kernels go to a folder of its own instead, $XDG_CACHE_HOME/lasmesh/pocl
// (~/.cache/lasmesh/pocl), documented in docs/usage.md: safe to delete at any time. Turning the
// cache off (POCL_KERNEL_CACHE=0) would recompile the kernels, about a second, on every run.
#include "kernel_cache.hpp"

#include <cstdlib>
#include <filesystem>
#include <string>

namespace lasmesh::cli {

void use_own_kernel_cache() {
    if (const char* set = std::getenv("POCL_CACHE_DIR"); set && *set) return; // the user's choice
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    const char* home = std::getenv("HOME");
    std::filesystem::path folder;
    if (xdg && *xdg) folder = xdg;
    else if (home && *home) folder = std::filesystem::path(home) / ".cache";
    else return;
    folder /= "lasmesh/pocl";
    std::error_code ignored; // no cache folder: PoCL compiles without caching, as before
    std::filesystem::create_directories(folder, ignored);
    ::setenv("POCL_CACHE_DIR", folder.c_str(), 1); // also over an empty value, which PoCL asserts on
}

} // namespace lasmesh::cli
