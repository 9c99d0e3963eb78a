// SPDX-License-Identifier: Apache-2.0
// An output written under a temporary name beside its final path and renamed into place only
// when complete, so a failed or interrupted run never leaves a partial file under the final name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace lasmesh {

class OutputFile {
  public:
    // Creates ".lasmesh-XXXXXX.tmp" in the folder of `path`; throws Error (output) when the folder is missing or
    // read-only.
    explicit OutputFile(std::string path);
    ~OutputFile(); // removes the temporary file unless commit() succeeded
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    void write(const void* data, std::size_t size); // throws Error (output), e.g. on a full disk
    void write(const std::string& text) { write(text.data(), text.size()); }
    // Flushes and closes the temporary file (the step where a full disk shows); throws Error
    // (output). Nothing is renamed yet.
    void finish();
    // finish(), then renames the file to its final path; throws Error (output).
    void commit();
    const std::string& path() const { return path_; }
    std::uint64_t bytes() const { return bytes_; } // written so far

  private:
    [[noreturn]] void fail(const std::string& doing);
    std::string path_, temporary_;
    std::unique_ptr<char[]> buffer_; // stdio's buffer for file_: 1 MiB, fewer write calls
    std::FILE* file_ = nullptr;
    std::uint64_t bytes_ = 0;
    bool committed_ = false;
};

// Several outputs of one run, all or none: every file is finished first (so a full disk fails
// before any rename), then each renamed; when a rename fails, those already renamed are removed
// again. Throws Error (output).
void commit_all(const std::vector<std::unique_ptr<OutputFile>>& files);

// Removes the temporary file of every OutputFile not yet committed and blocks any further
// create or commit, for good: for a termination signal's cleanup right before the process exits
// (src/cli/signals.cpp). Never call it from an asynchronous signal handler (it takes a mutex).
void remove_unfinished_outputs();

// Writes `bytes` encoded in memory (Draco, glTF) as the whole of `path`, through an OutputFile.
// `encode` runs first; its errors are prefixed with the path. An empty mesh is refused.
void write_encoded(const std::string& path, const std::string& format, bool empty,
                   const std::function<std::string()>& encode);

// Checks before any work that `path`'s folder exists and is writable; throws Error (output).
void check_output_folder(const std::string& path);

} // namespace lasmesh
