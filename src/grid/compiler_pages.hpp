// SPDX-License-Identifier: Apache-2.0
// Internal: the OpenCL compiler's pages handed back once the kernels are built.
//
//     program.build(...);
//     release_compiler_pages(); // the compiler's code no longer counts in this process's memory
//
// On a CPU device the OpenCL runtime (PoCL) loads its compiler, LLVM and clang, into the
// process; preparing a program, even one its cache holds, reads some 70 MB of their code and
// tables, which would then stay resident for the whole run: more than a tile job's own grid.
// They are clean pages of the library files, which the system can always read again from its
// page cache, so once the kernels are built they are dropped from this process (madvise
// MADV_DONTNEED); a later build faults back what it uses. Pages the loader wrote (relocated
// data: private copies, which dropping would lose) are never touched: only mappings that hold
// no private page.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace lasmesh {

// Whether a mapped file is part of an OpenCL compiler (LLVM or clang, by its file name).
bool is_compiler_library(std::string_view path);

// A read-only mapping of a compiler library that holds no private page, and its bytes resident.
struct CompilerMapping {
    std::uintptr_t begin = 0, end = 0;
    std::size_t resident = 0;
};
// This process's such mappings, from /proc/self/smaps (none where the system has no /proc).
std::vector<CompilerMapping> compiler_mappings();

// Drops the resident pages of compiler_mappings() from this process; the bytes dropped.
std::size_t release_compiler_pages();

} // namespace lasmesh
