// Helpers for the scene tests: paths into the source tree, a scratch directory, error messages.
#pragma once
#include <clsph/error.hpp>

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <cstdlib>
#include <random>
#include <string>

namespace scene_test {

inline std::string source_path(const std::string& relative) { return std::string(CLSPH_SOURCE_DIR) + "/" + relative; }
inline std::string corpus(const std::string& name) { return source_path("tests/scene/corpus/" + name); }

// A fresh directory under the system's temporary directory, removed with everything in it.
class TempDir {
public:
    TempDir() {
        std::random_device rd;
        path_ = std::filesystem::temp_directory_path() / ("clsph-scene-test-" + std::to_string(rd()));
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

inline void write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    REQUIRE(out.good());
}

// The message of the exception of type E that f throws; fails the test if it throws none.
template <class E = clsph::SceneError, class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    FAIL("expected an exception, none was thrown");
    return {};
}

// A seed from std::random_device, printed so that a failure can be reproduced: CLSPH_TEST_SEED
// (as the device tests take it) gives it back.
inline unsigned fresh_seed() {
    const char* env = std::getenv("CLSPH_TEST_SEED");
    const unsigned seed = env && *env ? static_cast<unsigned>(std::stoul(env)) : std::random_device{}();
    MESSAGE("random seed " << seed);
    return seed;
}

}  // namespace scene_test
