// SPDX-License-Identifier: Apache-2.0
// PoCL caches every compiled kernel under ~/.cache/pocl/kcache, shared with every other OpenCL
// program, and a write cut short (a full disk, `ulimit -f`) leaves empty files there that nobody
// knows to remove. lasmesh's kernels go to a folder of its own instead, $XDG_CACHE_HOME/lasmesh/pocl
// (~/.cache/lasmesh/pocl), documented in docs/usage.md: safe to delete at any time. Turning the
// cache off (POCL_KERNEL_CACHE=0) would recompile the kernels, about a second, on every run; a
// folder PoCL cannot write makes it find no platform at all, so an unwritable one is replaced by a
// temporary folder for the run.
#include "kernel_cache.hpp"

#include "number_text.hpp"

#include <cstdlib>
#include <filesystem>
#include <string>

#include <sys/resource.h>
#include <unistd.h>

namespace lasmesh::cli {

namespace {

// Measured: compiling lasmesh's kernels writes files of up to about 1.5 MiB (PoCL 3.1, LLVM 14);
// under a 1 MiB limit LLVM stops, under 2 MiB it does not.
constexpr std::uint64_t compiler_file_bytes = 4ull << 20;

bool writable_folder(const std::filesystem::path& folder) {
    std::error_code error;
    std::filesystem::create_directories(folder, error);
    return std::filesystem::is_directory(folder, error) && ::access(folder.c_str(), W_OK | X_OK) == 0;
}

} // namespace

KernelCache::KernelCache() {
    if (const char* set = std::getenv("POCL_CACHE_DIR"); set && *set) return; // the user's choice
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    const char* home = std::getenv("HOME");
    std::filesystem::path folder;
    if (xdg && *xdg)
        folder = xdg;
    else if (home && *home)
        folder = std::filesystem::path(home) / ".cache";
    if (!folder.empty()) {
        folder /= "lasmesh/pocl";
        if (writable_folder(folder)) {
            ::setenv("POCL_CACHE_DIR", folder.c_str(), 1); // also over an empty value, which PoCL asserts on
            return;
        }
    }
    std::error_code error;
    std::string pattern = (std::filesystem::temp_directory_path(error) / "lasmesh-pocl-XXXXXX").string();
    if (!error && ::mkdtemp(pattern.data())) {
        temporary_ = pattern;
        ::setenv("POCL_CACHE_DIR", temporary_.c_str(), 1);
    }
}

KernelCache::~KernelCache() {
    std::error_code ignored;
    if (!temporary_.empty()) std::filesystem::remove_all(temporary_, ignored);
}

std::string KernelCache::problem() const {
    rlimit limit{};
    if (::getrlimit(RLIMIT_FSIZE, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY ||
        limit.rlim_cur >= compiler_file_bytes)
        return "";
    const char* folder = std::getenv("POCL_CACHE_DIR");
    return "the file size limit (ulimit -f) of " + mebibytes(limit.rlim_cur) + " is below the " +
           mebibytes(compiler_file_bytes) + " the OpenCL compiler may write for lasmesh's kernels" +
           (folder ? std::string(" (into ") + folder + ")" : std::string()) + ": raise it, e.g. ulimit -f 65536";
}

} // namespace lasmesh::cli
