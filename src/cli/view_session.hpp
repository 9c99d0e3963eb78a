// SPDX-License-Identifier: Apache-2.0
// What `lasmesh view` holds between requests: the inputs accumulated once, the options of the
// mesh shown, that mesh as the page shows it, and the progress of the job running. A new mesh
// with other extraction options (iso, surface, simplify bound, smallest piece) re-uses the
// accumulated grid (build_mesh of an AccumulatedInputs); another grid reads the inputs again.
// Save writes the command line's outputs with the options shown, through the same library call,
// so they are the bytes the equivalent command line writes.
#pragma once

#include "io/json.hpp"
#include "lasmesh/build_mesh.hpp"
#include "mesh_command.hpp"

#include <atomic>
#include <memory>
#include <mutex>
#include <ostream>
#include <string>
#include <vector>

namespace lasmesh::cli {

// A job asked for while another runs (the page says so and waits).
struct SessionBusy {};

class ViewSession {
  public:
    // Reads and accumulates the inputs, then meshes them with `options`; throws Error as the
    // meshing command does. Lines about each job go to `log`.
    ViewSession(const MeshOptions& options, std::ostream& log);

    // The page without a mesh (it fetches mesh_data), with `live` (JSON: the server's token and
    // the state) for its controls.
    std::string page(const Json& live) const;
    // The current mesh as the page decodes it (zlib of the page's mesh data).
    std::shared_ptr<const std::string> mesh_data() const;
    // The options shown and what the controls need: their text, the outputs Save may write,
    // the equivalent command line, whether the grid may change (the inputs can be read again).
    Json state() const;
    // Meshes again with the settings' option text ({"grid":"512","iso":"auto","simplify":
    // "0.25cell",...}); returns the new state with "reread" and "seconds". Throws Error (usage)
    // for option text the command line would refuse, SessionBusy while a job runs.
    Json remesh(const Json& settings);
    // Writes the chosen outputs (each one of the command line's) with the options shown;
    // returns what was written and the command line that writes the same.
    Json save(const std::vector<std::string>& outputs);
    // {"stage": "...", "points": N, "points_total": M, "busy": true|false}
    Json progress() const;

  private:
    // The mesh shown, the options it was made with and the accumulation it was made from.
    struct Shown {
        MeshOptions options;
        std::shared_ptr<const AccumulatedInputs> read;
        std::shared_ptr<const std::string> mesh_data;
        std::string facts; // the run report JSON of the mesh shown
        std::size_t triangles = 0;
    };
    class Watch;
    std::shared_ptr<const Shown> mesh_with(const MeshOptions& options, std::shared_ptr<const AccumulatedInputs> read,
                                           Watch& watch);
    std::shared_ptr<const Shown> shown() const;

    std::ostream& log_;
    std::vector<std::string> inputs_;
    std::mutex job_;                 // one mesh or save at a time (held by a Watch)
    mutable std::mutex shown_mutex_; // guards shown_ while it is replaced
    std::shared_ptr<const Shown> shown_;
    mutable std::mutex stage_mutex_;
    std::string stage_ = "idle";
    std::atomic<std::uint64_t> points_{0}, points_total_{0};
    std::atomic<bool> busy_{false};
};

} // namespace lasmesh::cli
