// SPDX-License-Identifier: Apache-2.0
// OutputFile: temporary file, buffered writes with every error checked, rename at the end.
#include "io/output_file.hpp"

#include "lasmesh/error.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace lasmesh {

namespace {
// The temporary files of the OutputFiles alive now, so that a termination signal can remove
// them (remove_unfinished_outputs). Process-wide because a signal is: the library's one global.
// Allocated once and never destroyed, so a signal during static destruction finds it intact.
struct Unfinished {
    std::mutex mutex;
    std::vector<std::string> paths;
};
Unfinished& unfinished() {
    static Unfinished* registry = new Unfinished;
    return *registry;
}

void forget(const std::string& temporary) { // caller holds the mutex
    auto& paths = unfinished().paths;
    for (auto it = paths.begin(); it != paths.end(); ++it)
        if (*it == temporary) {
            paths.erase(it);
            return;
        }
}

std::string folder_of(const std::string& path) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    return parent.empty() ? "." : parent.string();
}
} // namespace

void check_output_folder(const std::string& path) {
    const std::string folder = folder_of(path);
    if (!std::filesystem::is_directory(folder))
        throw Error(ErrorKind::output, path + ": the folder " + folder + " does not exist");
    if (::access(folder.c_str(), W_OK) != 0)
        throw Error(ErrorKind::output, path + ": cannot write in " + folder + ": " + std::strerror(errno));
}

// mkstemp creates files readable by their owner only; a finished output gets the mode any new
// file gets (0666 less the umask), read once: umask() can only be read by setting it.
static mode_t new_file_mode() {
    static const mode_t mode = [] {
        const mode_t mask = ::umask(0);
        ::umask(mask);
        return 0666 & ~mask;
    }();
    return mode;
}

OutputFile::OutputFile(std::string path) : path_(std::move(path)) {
    // A short name of its own in the output's folder (the rename must not cross file systems):
    // "<path>.<pid>.tmp" would not fit beside a legal 250-character name. Recognisable, for
    // removal after a kill -9 (docs/usage.md).
    std::string pattern = folder_of(path_) + "/.lasmesh-XXXXXX.tmp";
    // Created and registered under the lock: no moment where the file exists unregistered.
    std::lock_guard lock(unfinished().mutex);
    const int fd = ::mkstemps(pattern.data(), 4);
    if (fd < 0)
        throw Error(ErrorKind::output,
                    path_ + ": cannot create a temporary file in " + folder_of(path_) + ": " + std::strerror(errno));
    temporary_ = pattern;
    unfinished().paths.push_back(temporary_);
    ::fchmod(fd, new_file_mode());
    file_ = ::fdopen(fd, "wb");
    if (!file_) {
        const int error = errno;
        ::close(fd);
        ::unlink(temporary_.c_str());
        forget(temporary_);
        throw Error(ErrorKind::output, path_ + ": cannot open " + temporary_ + ": " + std::strerror(error));
    }
    constexpr std::size_t buffer_size = 1 << 20;
    buffer_ = std::make_unique_for_overwrite<char[]>(buffer_size);
    std::setvbuf(file_, buffer_.get(), _IOFBF, buffer_size);
}

OutputFile::~OutputFile() {
    if (file_) std::fclose(file_);
    if (committed_) return;
    std::lock_guard lock(unfinished().mutex);
    std::remove(temporary_.c_str());
    forget(temporary_);
}

void OutputFile::fail(const std::string& doing) {
    std::string reason = std::strerror(errno);
    if (errno == ENOSPC || errno == EDQUOT || errno == EFBIG) reason += ": free some space or write elsewhere";
    throw Error(ErrorKind::output, path_ + ": " + doing + " failed: " + reason);
}

void OutputFile::write(const void* data, std::size_t size) {
    if (size && std::fwrite(data, 1, size, file_) != size) fail("writing");
    bytes_ += size;
}

void OutputFile::finish() {
    if (!file_) return;
    if (std::fflush(file_) != 0) fail("writing");
    const int closed = std::fclose(file_);
    file_ = nullptr;
    if (closed != 0) fail("closing");
}

void OutputFile::commit() {
    finish();
    // Under the lock, so once remove_unfinished_outputs() has started no output appears.
    std::lock_guard lock(unfinished().mutex);
    if (std::rename(temporary_.c_str(), path_.c_str()) != 0) fail("renaming " + temporary_ + " to it");
    forget(temporary_);
    committed_ = true;
}

void commit_all(const std::vector<std::unique_ptr<OutputFile>>& files) {
    for (const auto& file : files) file->finish();
    std::size_t renamed = 0;
    try {
        for (; renamed < files.size(); ++renamed) files[renamed]->commit();
    } catch (const Error&) {
        // Undo: the run fails, so none of its outputs may stay (a file it replaced is gone, though).
        for (std::size_t i = 0; i < renamed; ++i) std::remove(files[i]->path().c_str());
        throw;
    }
}

void remove_unfinished_outputs() {
    // Keeps the lock for good: the caller exits next, and no output may be created or committed
    // in between by another thread.
    unfinished().mutex.lock();
    for (const std::string& temporary : unfinished().paths) ::unlink(temporary.c_str());
}

void write_encoded(const std::string& path, const std::string& format, bool empty,
                   const std::function<std::string()>& encode) {
    if (empty) throw Error(ErrorKind::output, path + ": the mesh has no triangles, " + format + " cannot hold it");
    std::string bytes;
    try {
        bytes = encode();
    } catch (const Error& e) {
        throw Error(e.kind(), path + ": " + e.what());
    }
    OutputFile out(path);
    out.write(bytes);
    out.commit();
}

} // namespace lasmesh
