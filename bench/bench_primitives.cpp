// clsph-bench-primitives: radix sort (pairs/s at 16-, 24- and 32-bit keys) and exclusive scan (GB/s
// of bytes read + written) from 2^min to 2^max elements per device, each next to the same device's
// device-to-device copy bandwidth (clEnqueueCopyBuffer, bytes read + written). Every figure is the
// median (min-max) of timed repeats after warm-up runs, and what was timed is checked against the
// CPU once per size. --tune sweeps launch shapes at one size (to choose the defaults).
#include "bench_util.hpp"
#include "device/primitives.hpp"

#include "clsph/devices.hpp"
#include "clsph/error.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <numeric>
#include <random>
#include <sstream>
#include <vector>

using namespace clsph;
using u32 = std::uint32_t;

namespace {

struct Options {
    std::string devices;
    int min_log2 = 16, max_log2 = 26;
    int warmup = 2, repeats = 10;
    bool tune = false;
    int tune_log2 = 24;
};

// The pristine unsorted input on host and device, and the buffers a sort works in.
struct SortInput {
    std::vector<u32> keys;
    cl_rt::Buffer pristine_keys, pristine_values, keys_buf, values_buf;
    std::size_t n = 0;

    SortInput(cl_rt::Device& dev, std::size_t count, std::mt19937_64& rng) : keys(count), n(count) {
        for (auto& k : keys) k = static_cast<u32>(rng());  // bits above key_bits set: carried, ignored
        std::vector<u32> values(n);
        std::iota(values.begin(), values.end(), 0u);
        pristine_keys = dev.alloc(n * sizeof(u32), "bench keys (pristine)");
        pristine_values = dev.alloc(n * sizeof(u32), "bench values (pristine)");
        keys_buf = dev.alloc(n * sizeof(u32), "bench keys");
        values_buf = dev.alloc(n * sizeof(u32), "bench values");
        dev.write(pristine_keys, keys.data(), n);
        dev.write(pristine_values, values.data(), n);
    }
    void restore(cl_rt::Device& dev) {
        dev.copy(pristine_keys, keys_buf, n * sizeof(u32));
        dev.copy(pristine_values, values_buf, n * sizeof(u32));
    }
};

// A stable sort on the masked key is the only permutation with: values a permutation of 0..n-1,
// keys[i] == input[values[i]], masked keys non-decreasing, and values increasing within equal keys.
// Checking that is O(n), which keeps validation at 2^26 cheap.
std::string validate_sort(cl_rt::Device& dev, SortInput& in, unsigned key_bits) {
    std::vector<u32> k(in.n), v(in.n);
    dev.read(in.keys_buf, k.data(), in.n);
    dev.read(in.values_buf, v.data(), in.n);
    const u32 mask = key_bits == 32 ? ~0u : (1u << key_bits) - 1u;
    std::vector<bool> seen(in.n, false);
    for (std::size_t i = 0; i < in.n; ++i) {
        std::ostringstream why;
        if (v[i] >= in.n || seen[v[i]]) why << "values[" << i << "] = " << v[i] << " is not a permutation";
        else if (k[i] != in.keys[v[i]]) why << "keys[" << i << "] does not belong to its value";
        else if (i > 0 && (k[i - 1] & mask) > (k[i] & mask)) why << "keys[" << i - 1 << ".." << i << "] out of order";
        else if (i > 0 && (k[i - 1] & mask) == (k[i] & mask) && v[i - 1] > v[i]) why << "unstable at " << i;
        if (!why.str().empty()) return why.str();
        seen[v[i]] = true;
    }
    return {};
}

std::string validate_scan(cl_rt::Device& dev, const std::vector<u32>& in, const cl_rt::Buffer& out) {
    std::vector<u32> got(in.size() + 1);
    dev.read(out, got.data(), got.size());
    u32 sum = 0;
    for (std::size_t i = 0; i <= in.size(); ++i) {
        if (got[i] != sum) return "out[" + std::to_string(i) + "] wrong";
        if (i < in.size()) sum += in[i];
    }
    return {};
}

void fail_if(const std::string& why, const std::string& what) {
    if (!why.empty()) throw Error("validation failed: " + what + ": " + why);
}

bench::Summary time_sort(cl_rt::Device& dev, device::RadixSort& sorter, SortInput& in, unsigned bits, const Options& o) {
    return bench::measure(o.warmup, o.repeats, [&] {
        return bench::time_launches(
            dev, [&] { sorter.sort(in.keys_buf, in.values_buf, in.n, bits); }, [&] { in.restore(dev); });
    });
}

void bench_sizes(cl_rt::Device& dev, const Options& o, std::mt19937_64& rng) {
    device::Scan scan(dev);
    device::RadixSort sorter(dev);
    std::cout << "timing: " << (dev.quirks().fake_event_timestamps ? "host clocks (this driver's events are fake)" : "device events")
              << "; sort: " << sorter.config().digit_bits << "-bit digits, tiles of " << sorter.tile() << " pairs ("
              << sorter.config().work_group << " x " << sorter.config().items << "); scan: tiles of " << scan.tile()
              << "\n\n";
    std::cout << "| elements | copy GB/s | scan GB/s | scan / copy | sort 16-bit Gpairs/s | sort 24-bit Gpairs/s | "
                 "sort 32-bit Gpairs/s |\n|---|---|---|---|---|---|---|\n";
    for (int lg = o.min_log2; lg <= o.max_log2; ++lg) {
        const std::size_t n = std::size_t{1} << lg;
        const double words = static_cast<double>(n);
        // Copy: the bandwidth the same device reaches moving n words (read + write counted).
        auto a = dev.alloc(n * sizeof(u32), "bench copy src");
        auto b = dev.alloc((n + 1) * sizeof(u32), "bench copy dst / scan out");
        dev.fill(a, u32{1}, n);
        const auto copy = bench::measure(o.warmup, o.repeats, [&] { return bench::time_copy(dev, a, b, n * sizeof(u32)); });
        // Scan: n words read, n + 1 written.
        std::vector<u32> in(n);
        for (auto& x : in) x = static_cast<u32>(rng() % 16);
        dev.write(a, in.data(), n);
        const auto sc = bench::measure(o.warmup, o.repeats, [&] {
            return bench::time_launches(dev, [&] { scan.exclusive(a, b, n); });
        });
        fail_if(validate_scan(dev, in, b), "scan of " + std::to_string(n));
        a = cl_rt::Buffer();
        b = cl_rt::Buffer();

        SortInput si(dev, n, rng);
        std::string sort_cells;
        for (unsigned bits : {16u, 24u, 32u}) {
            const auto t = time_sort(dev, sorter, si, bits, o);
            fail_if(validate_sort(dev, si, bits), std::to_string(bits) + "-bit sort of " + std::to_string(n));
            sort_cells += " " + bench::rate_cell(t, words * 1e-9, 3) + " |";
        }
        std::ostringstream pct;
        pct << std::fixed << std::setprecision(0) << 100.0 * copy.median / sc.median * (2.0 * words + 1) / (2.0 * words)
            << " %";
        std::cout << "| 2^" << lg << " | " << bench::rate_cell(copy, 8.0 * words * 1e-9) << " | "
                  << bench::rate_cell(sc, 4.0 * (2.0 * words + 1) * 1e-9) << " | " << pct.str() << " |" << sort_cells
                  << std::endl;
    }
}

// Where a 24-bit sort spends its time, and how the sum of kernel times compares with what the host
// waits (launch gaps and queue overheads included).
void sort_profile(cl_rt::Device& dev, const Options& o, std::mt19937_64& rng) {
    const int lg = std::min(o.max_log2, 24);
    const std::size_t n = std::size_t{1} << lg;
    device::RadixSort sorter(dev);
    SortInput si(dev, n, rng);
    const auto events = time_sort(dev, sorter, si, 24, o);
    const auto wall = bench::measure(o.warmup, o.repeats, [&] {
        si.restore(dev);
        return bench::time_host(dev, [&] { sorter.sort(si.keys_buf, si.values_buf, n, 24); });
    });
    si.restore(dev);
    dev.finish();
    auto& prof = dev.profiler();
    prof.clear();
    prof.enable(true);
    sorter.sort(si.keys_buf, si.values_buf, n, 24);
    const auto stats = prof.stats();
    prof.enable(false);
    double total = 0;
    for (const auto& [name, k] : stats) total += k.seconds;
    std::cout << "\n24-bit sort of 2^" << lg << " pairs, " << sorter.passes(24) << " passes: median "
              << std::setprecision(3) << events.median * 1e3 << " ms of kernel time, " << wall.median * 1e3
              << " ms host wall (finish to finish)\n\n| launch | calls | ms | share |\n|---|---|---|---|\n";
    for (const auto& [name, k] : stats)
        std::cout << "| " << name << " | " << k.calls << " | " << std::fixed << std::setprecision(3) << k.seconds * 1e3
                  << " | " << std::setprecision(0) << 100.0 * k.seconds / total << " % |\n"
                  << std::defaultfloat;
    prof.clear();
}

void tune(cl_rt::Device& dev, const Options& o, std::mt19937_64& rng) {
    const std::size_t n = std::size_t{1} << o.tune_log2;
    std::cout << "\nTuning at 2^" << o.tune_log2 << ": 24-bit sort (G pairs/s)\n\n"
              << "| digit bits | work-group | items | tile | Gpairs/s |\n|---|---|---|---|---|\n";
    {
        SortInput si(dev, n, rng);
        struct Shape { unsigned digit; std::size_t wg, items; };
        std::vector<Shape> shapes;
        for (unsigned digit : {4u, 6u, 8u})
            for (std::size_t wg : {128u, 256u})
                for (std::size_t items : {8u, 12u, 16u}) shapes.push_back({digit, wg, items});
        shapes.push_back({5, 256, 16});
        shapes.push_back({7, 256, 16});
        for (const auto& s : shapes) {
            std::cout << "| " << s.digit << " | " << s.wg << " | " << s.items << " | " << s.wg * s.items << " | ";
            try {
                device::RadixSort::Config c;
                c.digit_bits = s.digit;
                c.work_group = s.wg;
                c.items = s.items;
                device::RadixSort sorter(dev, c);
                const auto t = time_sort(dev, sorter, si, 24, o);
                fail_if(validate_sort(dev, si, 24), "tuned sort");
                std::cout << bench::rate_cell(t, static_cast<double>(n) * 1e-9, 3) << " |" << std::endl;
            } catch (const Error& e) {
                std::cout << "n/a: " << std::string(e.what()).substr(0, 80) << " |" << std::endl;
            }
        }
    }
    const int scan_lg = std::max(o.tune_log2, std::min(o.max_log2, 26));
    const std::size_t m = std::size_t{1} << scan_lg;
    std::cout << "\nTuning at 2^" << scan_lg << ": scan (GB/s, bytes read + written)\n\n"
              << "| work-group | items | GB/s |\n|---|---|---|\n";
    auto a = dev.alloc(m * sizeof(u32), "tune scan in");
    auto b = dev.alloc((m + 1) * sizeof(u32), "tune scan out");
    std::vector<u32> in(m);
    for (auto& x : in) x = static_cast<u32>(rng() % 16);
    dev.write(a, in.data(), m);
    for (std::size_t wg : {64u, 128u, 256u})
        for (std::size_t items : {4u, 8u, 16u, 32u}) {
            std::cout << "| " << wg << " | " << items << " | ";
            try {
                device::Scan scan(dev, device::Scan::Config{wg, items, "scan"});
                const auto t = bench::measure(o.warmup, o.repeats, [&] {
                    return bench::time_launches(dev, [&] { scan.exclusive(a, b, m); });
                });
                fail_if(validate_scan(dev, in, b), "tuned scan");
                std::cout << bench::rate_cell(t, 4.0 * (2.0 * static_cast<double>(m) + 1) * 1e-9) << " |" << std::endl;
            } catch (const Error& e) {
                std::cout << "n/a: " << std::string(e.what()).substr(0, 80) << " |" << std::endl;
            }
        }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"clsph-bench-primitives: radix sort and scan throughput next to copy bandwidth"};
    Options o;
    o.devices = default_device_spec();
    app.add_option("--devices", o.devices, "devices to measure (all|gpu|cpu|0,2|platform:NAME)");
    app.add_option("--min-log2", o.min_log2, "smallest size, log2 of elements")->check(CLI::Range(1, 31));
    app.add_option("--max-log2", o.max_log2, "largest size, log2 of elements")->check(CLI::Range(1, 31));
    app.add_option("--warmup", o.warmup, "untimed runs first")->check(CLI::Range(0, 100));
    app.add_option("--repeats", o.repeats, "timed runs (median, min, max reported)")->check(CLI::Range(1, 1000));
    app.add_flag("--tune", o.tune, "also sweep sort and scan launch shapes");
    app.add_option("--tune-log2", o.tune_log2, "size for --tune, log2 of elements")->check(CLI::Range(10, 30));
    CLI11_PARSE(app, argc, argv);
    try {
        auto devices = cl_rt::open_devices(o.devices);
        std::mt19937_64 rng(12345);
        std::cout << "## clsph-bench-primitives, " << bench::today() << "\n\n`";
        for (int i = 0; i < argc; ++i) std::cout << (i ? " " : "") << argv[i];
        std::cout << "`; median (min-max) of " << o.repeats << " runs after " << o.warmup
                  << " warm-up runs; sort and scan times are kernel times (sum of their launches); every result "
                     "validated against the CPU once per size\n\n";
        for (auto& dev : devices) {
            std::cout << bench::header(*dev) << "\n";
            bench_sizes(*dev, o, rng);
            sort_profile(*dev, o, rng);
            if (o.tune) tune(*dev, o, rng);
            std::cout << std::endl;
        }
    } catch (const Error& e) {
        std::cerr << "clsph-bench-primitives: error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
