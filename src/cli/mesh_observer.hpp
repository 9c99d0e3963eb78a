// SPDX-License-Identifier: Apache-2.0
// What the meshing command shows while the library works: the progress line, the --verbose
// details and the warning about points outside the grid, all on stderr.
#pragma once

#include "lasmesh/build_mesh.hpp"
#include "progress.hpp"

#include <ostream>

namespace lasmesh::cli {

class MeshObserver : public BuildObserver {
  public:
    MeshObserver(std::ostream& out, bool progress, bool verbose, bool quiet);

    void stage_started(BuildStage stage, const std::string& what) override;
    void stage_ended(BuildStage stage, const RunReport& so_far) override;
    void points_read(std::uint64_t points, std::uint64_t points_total, std::uint64_t bytes,
                     std::optional<std::uint64_t> bytes_total) override;
    void detail(const std::string& line) override;

    void clear() { progress_.clear(); } // before the summary

  private:
    std::ostream& out_;
    Progress progress_;
    bool verbose_, quiet_;
};

} // namespace lasmesh::cli
