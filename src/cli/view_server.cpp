// SPDX-License-Identifier: Apache-2.0
#include "view_server.hpp"

#include "request_checks.hpp"

#include "lasmesh/error.hpp"
#include "option_parsing.hpp"

#include <httplib.h>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <thread>

extern char** environ;

namespace lasmesh::cli {

namespace {

std::string machine_name() {
    char name[256] = {};
    return ::gethostname(name, sizeof name - 1) == 0 ? std::string(name) : std::string();
}

void send_json(httplib::Response& response, const Json& json, int status = 200) {
    response.status = status;
    response.set_content(json_line(json), "application/json");
}

// The job's error as the page shows it: 400 for options, 409 while busy, 500 otherwise.
template <typename Job>
void answer(httplib::Response& response, Job&& job) {
    try {
        send_json(response, job());
    } catch (const SessionBusy&) {
        send_json(response, {{"error", "another mesh or save is running: wait for it"}}, 409);
    } catch (const Error& e) {
        const bool options = e.kind() == ErrorKind::usage || e.kind() == ErrorKind::input;
        send_json(response, {{"error", std::string(e.what()) + flag_hint(e)}}, options ? 400 : 500);
    } catch (const std::exception& e) {
        send_json(response, {{"error", std::string("internal error: ") + e.what()}}, 500);
    }
}

// Starts the desktop's browser on the URL; does not wait for it.
void open_browser(const std::string& url, std::ostream& log) {
    pid_t child = 0;
    const char* argv[] = {"xdg-open", url.c_str(), nullptr};
    if (posix_spawnp(&child, "xdg-open", nullptr, nullptr, const_cast<char* const*>(argv), environ) != 0) {
        log << "lasmesh view: cannot start a browser (xdg-open): open the URL yourself" << std::endl;
        return;
    }
    std::thread([child] { ::waitpid(child, nullptr, 0); }).detach();
}

} // namespace

void serve(ViewSession& session, const ServeOptions& options, std::ostream& out, std::ostream& log) {
    httplib::Server server;
    const std::string token = random_token(), machine = machine_name();
    const bool shared = !is_loopback(options.listen);
    int port = options.port;
    server.set_payload_max_length(1 << 16); // settings and output names: small
    server.set_default_headers({{"Cache-Control", "no-store"},
                                {"Referrer-Policy", "no-referrer"},
                                {"X-Content-Type-Options", "nosniff"},
                                {"X-Frame-Options", "DENY"}});
    server.set_pre_routing_handler([&](const httplib::Request& request, httplib::Response& response) {
        const bool host_ok = host_names_server(request.get_header_value("Host"), port, shared, machine);
        if (host_ok && same_token(request.get_param_value("token"), token))
            return httplib::Server::HandlerResponse::Unhandled;
        response.status = 403;
        response.set_content(host_ok ? "forbidden: the URL's token is missing or wrong\n"
                                     : "forbidden: this server answers to its own address only\n",
                             "text/plain");
        return httplib::Server::HandlerResponse::Handled;
    });
    server.Get("/", [&](const httplib::Request&, httplib::Response& response) {
        response.set_content(session.page({{"token", token}, {"state", session.state()}}), "text/html; charset=utf-8");
    });
    server.Get("/mesh", [&](const httplib::Request&, httplib::Response& response) {
        const std::shared_ptr<const std::string> data = session.mesh_data();
        response.set_content(*data, "application/octet-stream");
    });
    server.Get("/state", [&](const httplib::Request&, httplib::Response& response) {
        answer(response, [&] { return session.state(); });
    });
    server.Get("/progress", [&](const httplib::Request&, httplib::Response& response) {
        answer(response, [&] { return session.progress(); });
    });
    server.Post("/mesh", [&](const httplib::Request& request, httplib::Response& response) {
        answer(response, [&] { return session.remesh(Json::parse(request.body, nullptr, false)); });
    });
    server.Post("/save", [&](const httplib::Request& request, httplib::Response& response) {
        answer(response, [&] {
            const Json body = Json::parse(request.body, nullptr, false);
            std::vector<std::string> outputs;
            if (body.is_object() && body.contains("outputs") && body["outputs"].is_array())
                for (const Json& path : body["outputs"])
                    if (path.is_string()) outputs.push_back(path.get<std::string>());
            return session.save(outputs);
        });
    });
    port = options.port == 0 ? server.bind_to_any_port(options.listen) : options.port;
    if (port <= 0 || (options.port != 0 && !server.bind_to_port(options.listen, options.port)))
        throw Error(ErrorKind::usage, "cannot listen on " + options.listen + " port " + std::to_string(options.port) +
                                          ": the address is not this machine's, or the port is taken");
    const std::string host = options.listen.find(':') != std::string::npos ? "[" + options.listen + "]"
                             : shared && options.listen == "0.0.0.0"       ? machine
                                                                           : options.listen;
    const std::string url = "http://" + host + ":" + std::to_string(port) + "/?token=" + token;
    if (shared)
        log << "lasmesh view: warning: listening on " << options.listen
            << ": anyone who can reach this machine and has the URL can see the mesh and save the outputs" << std::endl;
    out << url << std::endl;
    log << "lasmesh view: open the URL above in a browser; Ctrl-C stops" << std::endl;
    if (options.open) open_browser(url, log);
    server.listen_after_bind();
}

} // namespace lasmesh::cli
