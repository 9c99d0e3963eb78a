// SPDX-License-Identifier: Apache-2.0
// release_compiler_pages: the compiler libraries' clean pages dropped from the process once the
// kernels are built (see compiler_pages.hpp for why).
#include "grid/compiler_pages.hpp"

#include <charconv>
#include <fstream>
#include <string>
#include <system_error>

#include <sys/mman.h>

namespace lasmesh {

bool is_compiler_library(std::string_view path) {
    const std::string_view name = path.substr(path.rfind('/') + 1);
    return name.starts_with("libLLVM") || name.starts_with("libclang");
}

namespace {

// The number at the start of `text` after any spaces, in `base`; false when there is none or it
// does not end where `end` says (npos: anywhere).
bool read_number(std::string_view text, int base, std::uint64_t& value, std::size_t end = std::string_view::npos) {
    const std::size_t first = text.find_first_not_of(' ');
    if (first == std::string_view::npos) return false;
    const auto [at, error] = std::from_chars(text.data() + first, text.data() + text.size(), value, base);
    return error == std::errc() && (end == std::string_view::npos || at == text.data() + end);
}

} // namespace

std::vector<CompilerMapping> compiler_mappings() {
    // /proc/self/smaps: a header line per mapping ("begin-end perms offset device inode path"),
    // then its fields, "Rss:" and "Anonymous:" (its private pages) among them, in kB. Whatever
    // does not read as expected leaves its mapping alone.
    std::ifstream smaps("/proc/self/smaps");
    std::vector<CompilerMapping> mappings;
    std::string text;
    CompilerMapping m;
    bool candidate = false;
    while (std::getline(smaps, text)) {
        const std::string_view line = text;
        const std::size_t dash = line.find('-'), space = line.find(' ');
        if (dash != std::string_view::npos && space != std::string_view::npos && dash < space) {
            std::uint64_t begin = 0, end = 0;
            const std::size_t path = line.find('/');
            candidate = read_number(line.substr(0, dash), 16, begin, dash) &&
                        read_number(line.substr(dash + 1, space - dash - 1), 16, end, space - dash - 1) &&
                        line.size() > space + 2 && line[space + 2] != 'w' && path != std::string_view::npos &&
                        is_compiler_library(line.substr(path));
            m = {static_cast<std::uintptr_t>(begin), static_cast<std::uintptr_t>(end), 0};
        } else if (candidate && line.starts_with("Rss:")) {
            std::uint64_t kb = 0;
            candidate = read_number(line.substr(4), 10, kb);
            m.resident = static_cast<std::size_t>(kb) * 1024;
        } else if (candidate && line.starts_with("Anonymous:")) {
            std::uint64_t kb = 1;
            if (read_number(line.substr(10), 10, kb) && kb == 0) mappings.push_back(m);
            candidate = false;
        }
    }
    return mappings;
}

std::size_t release_compiler_pages() {
    std::size_t dropped = 0;
    for (const CompilerMapping& m : compiler_mappings())
        if (m.resident > 0 && madvise(reinterpret_cast<void*>(m.begin), m.end - m.begin, MADV_DONTNEED) == 0)
            dropped += m.resident;
    return dropped;
}

} // namespace lasmesh
