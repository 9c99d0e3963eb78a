// SPDX-License-Identifier: Apache-2.0
// same_file: identity by device and inode, so "in.las", "./in.las" and a hard link all match; a
// path that does not exist yet has no inode, so its canonical folder plus name stands in.
#include "io/same_file.hpp"

#include "lasmesh/error.hpp"

#include <filesystem>
#include <map>
#include <sys/stat.h>
#include <unistd.h>

namespace lasmesh {

namespace {

std::string canonical_name(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code error;
    const fs::path p(path);
    const fs::path folder = fs::weakly_canonical(p.parent_path().empty() ? fs::path(".") : p.parent_path(), error);
    return (error ? p.parent_path() : folder).string() + "/" + p.filename().string();
}

// "-" is standard input: a file redirected into it (`lasmesh - -o in.ply < in.ply`) is still the
// file, and must not be overwritten by the run that reads it.
bool identity(const std::string& path, struct stat& s) {
    if (path == "-") return ::fstat(STDIN_FILENO, &s) == 0 && S_ISREG(s.st_mode);
    return ::stat(path.c_str(), &s) == 0;
}

} // namespace

bool same_file(const std::string& a, const std::string& b) {
    struct stat sa {
    }, sb{};
    const bool a_exists = identity(a, sa), b_exists = identity(b, sb);
    if (a_exists && b_exists) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    if (a_exists != b_exists) return false;
    if (a == "-" || b == "-") return false; // a pipe or terminal, or nothing: no file to lose
    return canonical_name(a) == canonical_name(b);
}

void check_distinct_files(const std::vector<std::pair<std::string, std::string>>& paths) {
    for (std::size_t i = 0; i < paths.size(); ++i)
        for (std::size_t j = i + 1; j < paths.size(); ++j) {
            const auto& [role_a, a] = paths[i];
            const auto& [role_b, b] = paths[j];
            if (!same_file(a, b)) continue;
            throw Error(ErrorKind::usage, role_b + " \"" + b + "\" and " + role_a + " \"" + a +
                                              "\" are the same file: writing one would destroy the other; "
                                              "give each output a path of its own");
        }
}

void check_distinct_inputs(const std::vector<std::string>& inputs,
                           const std::vector<std::pair<std::string, std::string>>& outputs) {
    std::map<std::pair<dev_t, ino_t>, const std::string*> seen; // by identity: a sort, not n^2 comparisons
    for (const std::string& input : inputs) {
        struct stat s {};
        if (!identity(input, s)) continue; // reading it will say what is wrong
        const auto [at, added] = seen.emplace(std::pair{s.st_dev, s.st_ino}, &input);
        if (!added)
            throw Error(ErrorKind::usage,
                        "the inputs \"" + *at->second + "\" and \"" + input +
                            "\" are the same file: its points would be counted twice; give each input once",
                        "inputs");
    }
    for (const auto& [role, path] : outputs) {
        struct stat s {};
        if (!identity(path, s)) continue;
        if (const auto at = seen.find({s.st_dev, s.st_ino}); at != seen.end())
            throw Error(ErrorKind::usage, role + " \"" + path + "\" and the input \"" + *at->second +
                                              "\" are the same file: writing one would destroy the other; "
                                              "give each output a path of its own");
    }
    check_distinct_files(outputs);
}

} // namespace lasmesh
