// SPDX-License-Identifier: Apache-2.0
// A progress line on a terminal: one line redrawn in place with the stage, the work done, the
// rate and, when the total is known, an estimate of the time left. Silent when disabled (stderr
// is not a terminal, or --quiet), so logs and pipes never see it.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

namespace lasmesh::cli {

class Progress {
  public:
    Progress(std::ostream& out, bool enabled);
    ~Progress() { clear(); }

    // Reading: points so far of `points_total`; input bytes consumed (compressed bytes for a
    // compressed stream) of `bytes_total` when the input's size is known.
    void reading(std::uint64_t points, std::uint64_t points_total, std::uint64_t bytes,
                 std::optional<std::uint64_t> bytes_total);
    void stage(const std::string& what); // a stage without a measure of its own: "extracting"
    void clear();                        // erases the line, before the summary is printed

  private:
    void draw(const std::string& text);
    std::ostream& out_;
    bool enabled_;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_, last_draw_;
};

// Whether standard error is a terminal.
bool stderr_is_terminal();

} // namespace lasmesh::cli
