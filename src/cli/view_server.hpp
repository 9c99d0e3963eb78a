// SPDX-License-Identifier: Apache-2.0
// `lasmesh view`'s web server (cpp-httplib, from Debian): the page and the current mesh, the
// controls' requests, nothing else. Safe by default:
// - it listens on 127.0.0.1 unless told an address to share on;
// - every request carries the random token printed in the URL, or gets 403;
// - the Host header must name this server (a loopback name, or with an address to share on, an
//   IP address or this machine's name) on its port, or the request gets 403: a web page elsewhere
//   cannot reach it through a DNS name rebound to 127.0.0.1;
// - responses are never cached and never send the URL (with its token) as a referrer;
// - Save writes only the outputs the command line named.
#pragma once

#include "view_session.hpp"

#include <ostream>
#include <string>

namespace lasmesh::cli {

struct ServeOptions {
    std::string listen = "127.0.0.1"; // the address to listen on
    int port = 0;                     // 0: any free port
    bool open = false;                // start the desktop's browser on the URL (xdg-open)
};

// Serves `session` until the process is stopped (Ctrl-C). Prints the URL with its token on
// `out`, notes on `log`. Throws Error (usage) when it cannot listen on the address and port.
void serve(ViewSession& session, const ServeOptions& options, std::ostream& out, std::ostream& log);

} // namespace lasmesh::cli
