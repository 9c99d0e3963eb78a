// SPDX-License-Identifier: Apache-2.0
#include "view_session.hpp"

#include "command_line.hpp"
#include "io/html_writer.hpp"
#include "lasmesh/error.hpp"
#include "number_text.hpp"
#include "option_parsing.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <filesystem>

namespace lasmesh::cli {

// The session's one job while it runs (SessionBusy when another holds it), and its progress for
// the page's progress bar.
class ViewSession::Watch : public BuildObserver {
  public:
    explicit Watch(ViewSession& session) : session_(session), job_(session.job_, std::try_to_lock) {
        if (!job_.owns_lock()) throw SessionBusy{};
        session_.busy_ = true;
        session_.points_ = 0;
        session_.points_total_ = 0;
    }
    ~Watch() override {
        set_stage("idle");
        session_.busy_ = false;
    }
    bool read_inputs = false; // this job read the inputs (for a grid, or thin parts again)

    void stage_started(BuildStage stage, const std::string& what) override {
        read_inputs = read_inputs || stage == BuildStage::read_accumulate;
        set_stage(what);
    }
    void points_read(std::uint64_t points, std::uint64_t points_total, std::uint64_t,
                     std::optional<std::uint64_t>) override {
        session_.points_ = points;
        session_.points_total_ = points_total;
    }

  private:
    void set_stage(const std::string& what) {
        const std::lock_guard lock(session_.stage_mutex_);
        session_.stage_ = what;
    }
    ViewSession& session_;
    std::unique_lock<std::mutex> job_;
};

namespace {

// The page's title: the input's name without extension, or "N files".
std::string shown_name(const std::vector<std::string>& inputs) {
    if (inputs.size() != 1) return std::to_string(inputs.size()) + " files";
    const std::string stem = std::filesystem::path(inputs.front()).stem().string();
    return inputs.front() == "-" || stem.empty() ? "lasmesh" : stem;
}

// The page's option text applied to the command line's: only what the page offers.
MeshOptions with_settings(MeshOptions o, const Json& settings) {
    if (!settings.is_object()) throw Error(ErrorKind::usage, "the settings must be a JSON object");
    const auto text = [&](const char* key) -> std::optional<std::string> {
        if (!settings.contains(key)) return std::nullopt;
        if (!settings[key].is_string()) throw Error(ErrorKind::usage, std::string(key) + " must be text");
        return settings[key].get<std::string>();
    };
    if (auto grid = text("grid")) o.grid.grid = *grid;
    if (auto voxel = text("voxel")) {
        if (voxel->empty()) {
            o.grid.voxel.reset();
        } else {
            double edge = 0;
            const auto [end, ec] = std::from_chars(voxel->data(), voxel->data() + voxel->size(), edge);
            if (ec != std::errc() || end != voxel->data() + voxel->size() || !(edge > 0) || !std::isfinite(edge))
                throw Error(ErrorKind::usage, "the cell edge must be a positive length, got \"" + *voxel + "\"",
                            "grid");
            o.grid.voxel = edge;
        }
    }
    if (auto iso = text("iso")) o.iso = *iso;
    if (auto surface = text("surface")) o.surface = *surface;
    if (auto simplify = text("simplify")) o.simplify = *simplify;
    if (auto min_piece = text("min_piece")) o.min_piece = *min_piece;
    // The closed surface's vertex placement has no meaning on the sheet.
    if (o.surface == "sheet") o.placement = MeshOptions().placement;
    return o;
}

bool reads_differently(const MeshOptions& a, const MeshOptions& b) {
    return a.grid.grid != b.grid.grid || a.grid.voxel != b.grid.voxel;
}

} // namespace

ViewSession::ViewSession(const MeshOptions& options, std::ostream& log) : log_(log), inputs_(all_inputs(options)) {
    const BuildOptions b = build_options(options, false);
    check_tile_option(b);
    if (inputs_.empty()) throw Error(ErrorKind::usage, "no input given: nothing to view", "inputs");
    log_ << "lasmesh view: reading "
         << (inputs_.size() == 1 ? inputs_.front() : std::to_string(inputs_.size()) + " files") << " and meshing it"
         << std::endl;
    Watch watch(*this);
    const auto start = std::chrono::steady_clock::now();
    shown_ =
        mesh_with(options, std::make_shared<const AccumulatedInputs>(accumulate_inputs(inputs_, b, &watch)), watch);
    log_ << "lasmesh view: " << shown_->read->report.points_read << " points read, " << shown_->triangles
         << " triangles, in "
         << two_digits(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()) << " s"
         << std::endl;
}

std::shared_ptr<const ViewSession::Shown>
ViewSession::mesh_with(const MeshOptions& options, std::shared_ptr<const AccumulatedInputs> read, Watch& watch) {
    BuildOptions b = build_options(options, false);
    b.outputs.clear();
    b.report.clear();
    b.keep_mesh = true;
    const BuildResult result = build_mesh(*read, b, &watch);
    auto shown = std::make_shared<Shown>();
    shown->options = options;
    shown->read = std::move(read);
    shown->facts = run_report_json(result.report);
    HtmlOptions page;
    page.name = shown_name(inputs_);
    page.facts_json = shown->facts;
    shown->mesh_data = std::make_shared<const std::string>(compress_html_mesh(*result.mesh, page));
    shown->triangles = result.mesh->triangles.size();
    return shown;
}

std::string ViewSession::page(const Json& live) const {
    std::string page = html_page_with(std::string()); // the page fetches the mesh, showing its progress
    // JSON in a <script> element: "</" would end the element early.
    std::string text = json_line(live);
    for (std::size_t at = 0; (at = text.find("</", at)) != std::string::npos; at += 3) text.replace(at, 2, "<\\/");
    const std::string element = "<script type=\"application/json\" id=\"lasmesh-live\">" + text + "</script>\n";
    page.insert(page.rfind("</body>"), element);
    return page;
}

std::shared_ptr<const std::string> ViewSession::mesh_data() const {
    return shown()->mesh_data;
}

Json ViewSession::state() const {
    const std::shared_ptr<const Shown> now = shown();
    const MeshOptions& o = now->options;
    Json outputs = Json::array();
    for (const std::string& path : o.outputs) outputs.push_back(path);
    if (!o.preview.empty()) outputs.push_back(o.preview);
    return Json{{"options",
                 {{"grid", o.grid.grid},
                  {"voxel", o.grid.voxel ? format_double(*o.grid.voxel) : std::string()},
                  {"iso", o.iso},
                  {"surface", o.surface},
                  {"simplify", o.simplify},
                  {"min_piece", o.min_piece}}},
                {"outputs", outputs},
                {"command", command_line(o)},
                {"triangles", now->triangles},
                {"grid_rereadable", std::find(inputs_.begin(), inputs_.end(), "-") == inputs_.end()},
                {"facts", Json::parse(now->facts)}};
}

std::shared_ptr<const ViewSession::Shown> ViewSession::shown() const {
    const std::lock_guard lock(shown_mutex_);
    return shown_;
}

Json ViewSession::remesh(const Json& settings) {
    Watch watch(*this); // before anything is checked: one job at a time
    const std::shared_ptr<const Shown> before_shown = shown();
    const MeshOptions& before = before_shown->options;
    const MeshOptions next = with_settings(before, settings);
    const BuildOptions b = build_options(next, false); // every option text checked before any work
    const bool reread = reads_differently(before, next);
    if (reread && std::find(inputs_.begin(), inputs_.end(), "-") != inputs_.end())
        throw Error(ErrorKind::usage,
                    "standard input cannot be read again for another grid: start lasmesh view with that grid", "grid");
    const auto start = std::chrono::steady_clock::now();
    const std::shared_ptr<const Shown> now = mesh_with(
        next,
        reread ? std::make_shared<const AccumulatedInputs>(accumulate_inputs(inputs_, b, &watch)) : before_shown->read,
        watch);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    {
        const std::lock_guard lock(shown_mutex_);
        shown_ = now;
    }
    log_ << "lasmesh view: " << now->triangles << " triangles in " << two_digits(seconds) << " s, "
         << (reread              ? "the inputs read again for the grid"
             : watch.read_inputs ? "the inputs read again for the thin parts at this iso"
                                 : "from the accumulated grid (no re-read)")
         << ": " << command_line(next) << std::endl;
    Json out = state();
    out["reread"] = reread;
    out["seconds"] = seconds;
    return out;
}

Json ViewSession::save(const std::vector<std::string>& chosen) {
    Watch watch(*this);
    const std::shared_ptr<const Shown> current = shown();
    MeshOptions o = current->options;
    if (chosen.empty()) throw Error(ErrorKind::usage, "choose an output to save", "outputs");
    // Only the command line's outputs: the page cannot name a path of its own.
    for (const std::string& path : chosen)
        if (std::find(o.outputs.begin(), o.outputs.end(), path) == o.outputs.end() && path != o.preview)
            throw Error(ErrorKind::usage, "\"" + path + "\" is not one of the outputs lasmesh view was started with",
                        "outputs");
    const auto keep = [&](const std::string& path) {
        return std::find(chosen.begin(), chosen.end(), path) != chosen.end();
    };
    std::erase_if(o.outputs, [&](const std::string& path) { return !keep(path); });
    if (!keep(o.preview)) o.preview.clear();
    const BuildResult result = build_mesh(*current->read, build_options(o, true), &watch);
    Json written = Json::array();
    for (const OutputReport& output : result.report.outputs)
        written.push_back({{"path", output.path}, {"bytes", output.bytes}});
    if (!o.report.empty()) written.push_back({{"path", o.report}});
    for (const OutputReport& output : result.report.outputs)
        log_ << "lasmesh view: saved " << output.path << " (" << output.bytes << " bytes)" << std::endl;
    return Json{{"written", written}, {"command", command_line(o)}};
}

Json ViewSession::progress() const {
    const std::lock_guard lock(stage_mutex_);
    return Json{
        {"busy", busy_.load()}, {"stage", stage_}, {"points", points_.load()}, {"points_total", points_total_.load()}};
}

} // namespace lasmesh::cli
