// Frame output (issue 20): write_vtu of one frame read from disk, raw and zlib-compressed
// (clsph run --compress) with 1 and --threads threads: median (min-max) of --repeats writes, the
// file size, and the compressed frame read back equal (validated once). Writes go to --out (the
// page cache, usually: this times the encoding, not the disk).
//   clsph-bench-frames FRAME.vtu [--out /tmp/clsph-bench-frame.vtu] [--threads 8] [--repeats 3]
#include <clsph/io.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <vector>

int main(int argc, char** argv) {
    CLI::App app{"clsph-bench-frames: the cost of writing a frame raw and compressed"};
    std::string frame, out = "/tmp/clsph-bench-frame.vtu";
    unsigned threads = 8;
    int repeats = 3;
    app.add_option("frame", frame, "a frame written by clsph run (.vtu or .pvtu)")->required();
    app.add_option("--out", out, "where the frames are written");
    app.add_option("--threads", threads, "compressing threads of the second compressed row");
    app.add_option("--repeats", repeats, "writes timed per row")->check(CLI::PositiveNumber);
    CLI11_PARSE(app, argc, argv);

    const clsph::Particles p = clsph::read_vtu(frame);
    std::printf("%zu particles from %s\n\n| form | threads | write s, median (min-max) | MB | of raw |\n|---|---|---|---|---|\n",
                p.size(), frame.c_str());
    double raw_mb = 0.0;
    for (const clsph::VtuFormat f : {clsph::VtuFormat{false, 1}, clsph::VtuFormat{true, 1}, clsph::VtuFormat{true, threads}}) {
        std::vector<double> t;
        for (int r = 0; r < repeats; ++r) {
            const auto start = std::chrono::steady_clock::now();
            clsph::write_vtu(out, p, clsph::FrameFields{}, f);
            t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        }
        std::sort(t.begin(), t.end());
        const double mb = static_cast<double>(std::filesystem::file_size(out)) / 1e6;
        if (!f.compress) raw_mb = mb;
        std::printf("| %s | %u | %.3f (%.3f-%.3f) | %.1f | %.2f |\n", f.compress ? "zlib" : "raw", f.threads, t[t.size() / 2],
                    t.front(), t.back(), mb, mb / raw_mb);
        if (f.compress) {
            const clsph::Particles q = clsph::read_vtu(out);
            if (q.size() != p.size() || q.id != p.id || q.position != p.position || q.velocity != p.velocity ||
                q.density != p.density || q.pressure != p.pressure) {
                std::fprintf(stderr, "clsph-bench-frames: the compressed frame does not read back equal\n");
                return 1;
            }
        }
    }
    std::filesystem::remove(out);
    return 0;
}
