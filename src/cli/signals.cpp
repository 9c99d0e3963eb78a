// SPDX-License-Identifier: Apache-2.0
// Termination signals: remove the unfinished outputs' temporary files, then exit 128 + signal.
//
// Why a thread with sigwait() rather than a signal handler: the cleanup walks a list of paths
// guarded by a mutex (OutputFile's registry), which an asynchronous handler may not touch. With
// the signals blocked in main() before TBB, PoCL or any other thread exists, every thread
// inherits the mask, so the kernel can deliver a process-directed SIGINT/SIGTERM/SIGHUP to none
// of them; it stays pending until the waiting thread takes it with sigwait(), in ordinary code.
#include "signals.hpp"

#include "io/output_file.hpp"

#include <csignal>
#include <cstdio>
#include <cstring>
#include <pthread.h>
#include <thread>
#include <unistd.h>

namespace lasmesh::cli {

void handle_signals() {
    // A closed pipe on stdout or stderr (`lasmesh info x.las | head -1`) must not kill the run
    // before it removes its temporary files: ignored, writes fail with EPIPE instead, and main()
    // reports a failed standard output with exit code 4.
    std::signal(SIGPIPE, SIG_IGN);
    // Likewise a file size limit (`ulimit -f`): SIGXFSZ would kill the run with a core dump and a
    // partial temporary file; ignored, write(2) fails with EFBIG and the run ends with exit 4.
    std::signal(SIGXFSZ, SIG_IGN);

    sigset_t termination;
    sigemptyset(&termination);
    for (int signal : {SIGINT, SIGTERM, SIGHUP}) {
        // An ignored signal stays ignored: nohup ignores SIGHUP, a shell script's background
        // jobs SIGINT, and Linux would still queue a blocked one for sigwait().
        struct sigaction current {};
        sigaction(signal, nullptr, &current);
        if (current.sa_handler != SIG_IGN) sigaddset(&termination, signal);
    }
    pthread_sigmask(SIG_BLOCK, &termination, nullptr);
    std::thread([termination] {
        int signal = 0;
        if (sigwait(&termination, &signal) != 0) return;
        remove_unfinished_outputs(); // and keeps any other thread from committing one
        std::fprintf(stderr, "lasmesh: stopped by SIG%s; unfinished outputs removed\n", sigabbrev_np(signal));
        _exit(128 + signal); // the shell's convention: 130 for SIGINT, 143 for SIGTERM
    }).detach();
}

} // namespace lasmesh::cli
