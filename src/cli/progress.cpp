// SPDX-License-Identifier: Apache-2.0
// Progress: redraws at most ten times a second; "\r" and an erase-line escape keep it on one line.
#include "progress.hpp"

#include <cstdio>
#include <iomanip>
#include <sstream>
#include <unistd.h>

namespace lasmesh::cli {

namespace {

std::string amount(double value, const char* unit) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(1);
    if (value >= 1e9)
        text << value / 1e9 << " G" << unit;
    else if (value >= 1e6)
        text << value / 1e6 << " M" << unit;
    else if (value >= 1e3)
        text << value / 1e3 << " k" << unit;
    else
        text << std::setprecision(0) << value << " " << unit;
    return text.str();
}

std::string clock_time(double seconds) {
    const long s = static_cast<long>(seconds + 0.5);
    char text[32];
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    return text;
}

} // namespace

bool stderr_is_terminal() {
    return ::isatty(STDERR_FILENO) == 1;
}

Progress::Progress(std::ostream& out, bool enabled)
    : out_(out), enabled_(enabled), start_(std::chrono::steady_clock::now()) {}

void Progress::reading(std::uint64_t points, std::uint64_t points_total, std::uint64_t bytes,
                       std::optional<std::uint64_t> bytes_total) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (drawn_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
    const double seconds = std::chrono::duration<double>(now - start_).count();
    std::ostringstream text;
    text << "reading   " << amount(static_cast<double>(points), "points");
    if (points_total > 0)
        text << " of " << amount(static_cast<double>(points_total), "") << " (" << 100 * points / points_total << "%)";
    text << ", " << amount(static_cast<double>(bytes), "B");
    if (bytes_total) text << " of " << amount(static_cast<double>(*bytes_total), "B");
    if (seconds > 0.2) {
        text << ", " << amount(points / seconds, "points/s");
        // The estimate follows the bytes where the size is known (compressed input included),
        // otherwise the promised point count.
        double done = 0;
        if (bytes_total && *bytes_total > 0)
            done = static_cast<double>(bytes) / static_cast<double>(*bytes_total);
        else if (points_total > 0)
            done = static_cast<double>(points) / static_cast<double>(points_total);
        if (done > 0.01) text << ", " << clock_time(seconds * (1 - done) / done) << " left";
    }
    draw(text.str());
    last_draw_ = now;
}

void Progress::stage(const std::string& what) {
    if (enabled_) draw(what);
}

void Progress::draw(const std::string& text) {
    out_ << "\r\x1b[K" << text << std::flush;
    drawn_ = true;
}

void Progress::clear() {
    if (!enabled_ || !drawn_) return;
    out_ << "\r\x1b[K" << std::flush;
    drawn_ = false;
}

} // namespace lasmesh::cli
