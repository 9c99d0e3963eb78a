// Helpers shared by the tests: temporary folders, whole-file I/O, generated LAS bytes.
#pragma once

#include "lasgen/las_writer.hpp"
#include "lasgen/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace test {

using Bytes = std::vector<std::byte>;

// A fresh folder under the system temp folder, removed with everything in it at scope exit.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::filesystem::path path() const { return path_; }
    std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    std::filesystem::path path_;
};

Bytes read_file(const std::string& path);
void write_file(const std::string& path, const Bytes& bytes);

// A whole LAS file of `count` points of `scene`, as lasgen would write it.
Bytes make_las(const lasgen::LasLayout& layout, const lasgen::Scene& scene, std::uint64_t count,
               std::uint64_t seed = 1);

// The shared LAS test corpus beside the checkout, or empty when it is absent.
std::filesystem::path shared_las_folder();

} // namespace test
