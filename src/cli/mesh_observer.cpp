// SPDX-License-Identifier: Apache-2.0
// MeshObserver: every line it prints first erases the progress line, so the two never mix.
#include "mesh_observer.hpp"

#include "grid_options.hpp"

namespace lasmesh::cli {

MeshObserver::MeshObserver(std::ostream& out, bool progress, bool verbose, bool quiet)
    : out_(out), progress_(out, progress && !quiet), verbose_(verbose), quiet_(quiet) {}

void MeshObserver::stage_started(BuildStage stage, const std::string& what) {
    // Reading has a measure of its own (points_read); the other stages show their name.
    if (stage != BuildStage::read_accumulate) progress_.stage(what);
}

void MeshObserver::stage_ended(BuildStage stage, const RunReport& so_far) {
    if (stage != BuildStage::read_accumulate || quiet_) return;
    progress_.clear();
    out_ << outside_advice(so_far.points_outside, so_far.points_read);
    for (const std::string& warning : so_far.warnings) out_ << warning << "\n";
}

void MeshObserver::points_read(std::uint64_t points, std::uint64_t points_total, std::uint64_t bytes,
                               std::optional<std::uint64_t> bytes_total) {
    progress_.reading(points, points_total, bytes, bytes_total);
}

void MeshObserver::detail(const std::string& line) {
    if (!verbose_) return;
    progress_.clear();
    out_ << line << "\n";
}

} // namespace lasmesh::cli
