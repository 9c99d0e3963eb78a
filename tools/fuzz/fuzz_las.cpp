// SPDX-License-Identifier: Apache-2.0
// libFuzzer target over everything that reads untrusted bytes before the device sees them:
// compressed-input detection and decoding (InputStream), the header and VLR parser
// (read_las_header), the coordinate system's VLRs (read_crs: GeoTIFF keys and WKT through PROJ),
// the LAZ decoder behind LasReader, and the record reader (scan_points).
// A lasmesh::Error is the expected answer to bad bytes; anything else (a crash, a sanitizer
// report, another exception) is a bug. Built and run by tools/fuzz.sh.
#include "lasmesh/error.hpp"
#include "lasmesh/las_reader.hpp"
#include "read/crs.hpp"
#include "read/las_scan.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <sys/mman.h>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // InputStream opens a path, so the bytes go to an in-memory file opened through /proc. One
    // for the whole run (static): creating one per input would cost a file descriptor each.
    static const int fd = memfd_create("fuzz_las", MFD_CLOEXEC);
    if (fd < 0 || ftruncate(fd, 0) != 0) std::abort();
    for (std::size_t done = 0; done < size;) {
        const ssize_t wrote = pwrite(fd, data + done, size - done, static_cast<off_t>(done));
        if (wrote <= 0) std::abort();
        done += static_cast<std::size_t>(wrote);
    }
    static const std::string path = "/proc/self/fd/" + std::to_string(fd);
    try {
        lasmesh::LasReader reader(path);
        lasmesh::read_crs(reader.header());
        // Small chunks: many reads, so records end at every position relative to a chunk.
        lasmesh::scan_points(reader, 3);
    } catch (const lasmesh::Error&) {
    }
    return 0;
}
