// Test helpers: temp folders, file I/O and LAS fixtures from the project's own generator.
#include "test_support.hpp"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace test {

TempDir::TempDir() {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("lasmesh-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
}

Bytes read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Bytes bytes(text.size());
    std::memcpy(bytes.data(), text.data(), text.size());
    return bytes;
}

void write_file(const std::string& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + path);
}

Bytes make_las(const lasgen::LasLayout& layout, const lasgen::Scene& scene, std::uint64_t count, std::uint64_t seed) {
    lasgen::LasLayout l = layout;
    for (int a = 0; a < 3; ++a) l.offset[a] = std::floor(scene.min[a]);
    Bytes file = lasgen::las_file_head(l, count, scene.min, scene.max, "test scene");
    const std::size_t length = lasgen::record_length(l);
    const std::size_t head = file.size();
    file.resize(head + count * length);
    for (std::uint64_t i = 0; i < count; ++i)
        lasgen::encode_record(l, lasgen::generate_point(scene, seed, i), i, file.data() + head + i * length);
    return file;
}

std::filesystem::path shared_las_folder() {
    // shared/ sits beside the checkout (CI clones main next to it); LASMESH_SHARED overrides.
    const char* override_dir = std::getenv("LASMESH_SHARED");
    std::filesystem::path shared = override_dir ? std::filesystem::path(override_dir)
                                                : std::filesystem::path(LASMESH_SOURCE_DIR).parent_path() / "shared";
    std::filesystem::path folder = shared / "data" / "las";
    return std::filesystem::exists(folder / "MANIFEST.tsv") ? folder : std::filesystem::path();
}

} // namespace test
