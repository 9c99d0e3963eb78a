// SPDX-License-Identifier: Apache-2.0
// release_compiler_pages: the compiler libraries' clean pages dropped from the process once the
// kernels are built (see compiler_pages.hpp for why).
#include "grid/compiler_pages.hpp"

#include <exception>
#include <fstream>
#include <string>

#include <sys/mman.h>

namespace lasmesh {

bool is_compiler_library(std::string_view path) {
    const std::string_view name = path.substr(path.rfind('/') + 1);
    return name.starts_with("libLLVM") || name.starts_with("libclang");
}

std::vector<CompilerMapping> compiler_mappings() {
    // /proc/self/smaps: a header line per mapping ("begin-end perms offset device inode path"),
    // then its fields, "Rss:" and "Anonymous:" (its private pages) among them, in kB.
    std::ifstream smaps("/proc/self/smaps");
    std::vector<CompilerMapping> mappings;
    std::string line;
    CompilerMapping m;
    bool candidate = false;
    while (std::getline(smaps, line)) {
        const std::size_t dash = line.find('-'), space = line.find(' ');
        if (dash != std::string::npos && space != std::string::npos && dash < space) {
            std::size_t digits = 0;
            try {
                m.begin = std::stoull(line.substr(0, dash), &digits, 16);
                m.end = std::stoull(line.substr(dash + 1, space - dash - 1), nullptr, 16);
            } catch (const std::exception&) {
                digits = 0;
            }
            const std::size_t path = line.find('/');
            candidate = digits == dash && line.size() > space + 2 && line[space + 2] != 'w' &&
                        path != std::string::npos && is_compiler_library(std::string_view(line).substr(path));
            m.resident = 0;
        } else if (candidate && line.starts_with("Rss:")) {
            m.resident = std::stoull(line.substr(4)) * 1024;
        } else if (candidate && line.starts_with("Anonymous:")) {
            if (std::stoull(line.substr(10)) == 0) mappings.push_back(m);
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
