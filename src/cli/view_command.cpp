// SPDX-License-Identifier: Apache-2.0
#include "view_command.hpp"

#include "io/html_writer.hpp"
#include "lasmesh/error.hpp"
#include "mesh_observer.hpp"
#include "option_parsing.hpp"
#include "view_session.hpp"

namespace lasmesh::cli {

CLI::App* add_view_command(CLI::App& app, ViewOptions& o) {
    CLI::App* view = app.add_subcommand(
        "view", "Mesh once, then show the mesh in a web browser, served from this machine: look, measure, mesh "
                "again with other options (without reading the points again unless the grid changes), save");
    view->footer("Examples:\n"
                 "  lasmesh view deck.las -o deck.ply -o deck.glb   the page's Save writes these two\n"
                 "  lasmesh view deck.las --open                    and start the desktop's browser on it\n"
                 "  lasmesh view deck.las --listen 0.0.0.0 --port 8080   share on the network (with a warning)");
    add_mesh_options(*view, o.mesh);
    view->add_option("--port", o.serve.port, "Port to listen on; 0 (the default): any free port")
        ->type_name("N")
        ->capture_default_str()
        ->check(whole_number(0, 65535));
    view->add_flag("--open", o.serve.open, "Start the desktop's web browser on the page (xdg-open)");
    view->add_option("--listen", o.serve.listen,
                     "Address to listen on; anything but 127.0.0.1 shares the page (and Save) with the network")
        ->type_name("ADDRESS")
        ->capture_default_str();
    return view;
}

void run_view(const ViewOptions& o, std::ostream& out, std::ostream& log) {
    if (html_viewer_script().empty()) // refused now, not in the browser
        throw Error(ErrorKind::output, "this lasmesh was built without its HTML viewer (three.js and esbuild from npm "
                                       "were not found when it was built: tools/build.sh installs them)");
    ViewSession session(o.mesh, log);
    serve(session, o.serve, out, log);
}

} // namespace lasmesh::cli
