#include "support/test_devices.hpp"

#include <cstdlib>
#include <iostream>
#include <memory>
#include "clsph/devices.hpp"
#include <string>

namespace clsph::test {

std::vector<cl_rt::Device*> devices() {
    static std::vector<std::unique_ptr<cl_rt::Device>> opened = [] {
        const char* env = std::getenv("CLSPH_TEST_DEVICES");
        auto d = cl_rt::open_devices(env && *env ? env : "all");
        std::cout << "[clsph tests] devices:";
        for (auto& dev : d) std::cout << "\n  " << dev->label();
        std::cout << std::endl;
        return d;
    }();
    std::vector<cl_rt::Device*> out;
    for (auto& d : opened) out.push_back(d.get());
    return out;
}

std::uint64_t seed() {
    static const std::uint64_t s = [] {
        const char* env = std::getenv("CLSPH_TEST_SEED");
        std::uint64_t v = env && *env ? std::strtoull(env, nullptr, 10)
                                      : (static_cast<std::uint64_t>(std::random_device{}()) << 32) ^ std::random_device{}();
        std::cout << "[clsph tests] seed " << v << " (rerun with CLSPH_TEST_SEED=" << v << ")" << std::endl;
        return v;
    }();
    return s;
}

std::mt19937_64 rng(std::uint64_t salt) { return std::mt19937_64(seed() ^ (salt * 0x9E3779B97F4A7C15ull)); }

}  // namespace clsph::test

namespace clsph::test {
std::string validation_device_spec() {
    if (const char* env = std::getenv("CLSPH_VALIDATION_DEVICES"); env && *env) return env;
    for (const auto& d : list_devices())
        if (d.name.find("pthread") != std::string::npos) return std::to_string(d.index);
    return "default";
}
std::string device_spec(std::size_t count) {
    const auto devs = devices();
    std::string s;
    for (std::size_t i = 0; i < count && i < devs.size(); ++i) s += (i ? "," : "") + std::to_string(devs[i]->info().index);
    return s;
}

}  // namespace clsph::test
