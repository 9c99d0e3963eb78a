// OutputFile: temporary file, buffered writes with every error checked, rename at the end.
#include "lasmesh/output_file.hpp"

#include "lasmesh/error.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <unistd.h>

namespace lasmesh {

namespace {
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

OutputFile::OutputFile(std::string path) : path_(std::move(path)) {
    temporary_ = path_ + "." + std::to_string(::getpid()) + ".tmp";
    file_ = std::fopen(temporary_.c_str(), "wb");
    if (!file_) throw Error(ErrorKind::output, path_ + ": cannot create " + temporary_ + ": " + std::strerror(errno));
    static thread_local char buffer[1 << 20];
    std::setvbuf(file_, buffer, _IOFBF, sizeof buffer);
}

OutputFile::~OutputFile() {
    if (file_) std::fclose(file_);
    if (!committed_) std::remove(temporary_.c_str());
}

void OutputFile::fail(const std::string& doing) {
    const std::string reason = std::strerror(errno);
    throw Error(ErrorKind::output, path_ + ": " + doing + " failed: " + reason);
}

void OutputFile::write(const void* data, std::size_t size) {
    if (size && std::fwrite(data, 1, size, file_) != size) fail("writing");
}

void OutputFile::commit() {
    if (std::fflush(file_) != 0) fail("writing");
    const int closed = std::fclose(file_);
    file_ = nullptr;
    if (closed != 0) fail("closing");
    if (std::rename(temporary_.c_str(), path_.c_str()) != 0) fail("renaming " + temporary_ + " to it");
    committed_ = true;
}

} // namespace lasmesh
