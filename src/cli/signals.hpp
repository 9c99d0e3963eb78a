// SPDX-License-Identifier: Apache-2.0
// What the command does on SIGINT, SIGTERM, SIGHUP, SIGPIPE and SIGXFSZ (see signals.cpp).
#pragma once

namespace lasmesh::cli {

// Call first thing in main(), before any thread starts: every thread created later inherits the
// blocked signal mask, so one dedicated thread receives the termination signals.
void handle_signals();

} // namespace lasmesh::cli
