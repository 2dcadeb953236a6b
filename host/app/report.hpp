// What `clsph run` prints when a run ends: the summary line and the --profile kernel table.
#pragma once
#include <clsph/simulation.hpp>

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace clsph::app {

struct RunTotals {
    std::string outcome;            // "completed", "interrupted", "failed"
    StepInfo last;                  // the last step taken
    std::uint64_t steps = 0;        // steps taken by this run
    double setup_seconds = 0.0;     // scene build, device set-up, kernel builds
    double loop_seconds = 0.0;      // stepping, probes and frame downloads
    double particle_steps = 0.0;    // sum over steps of the particle count
    std::size_t fluid = 0;
    std::size_t frames = 0;
    std::string out_dir;
    std::string collection;         // the .pvd
    std::vector<std::string> devices;  // a line per device: name and its share
    // run.list_buffer > 0: the cell tables' builds since the start and the buffer (else 0: every step).
    std::size_t table_builds = 0;
    double list_buffer = 0.0;
    // Of `steps`, those taken ahead of the host (the rest waited for on the host).
    std::uint64_t steps_ahead = 0;
    std::uint64_t steps_thrown = 0;  // computed ahead and thrown away (behind a halted step)
};

void print_summary(std::ostream& os, const RunTotals& t);

// Per-kernel calls, total ms, ms per call and share of the kernel total, largest first; with
// several devices each kernel's calls and times are summed over them.
void print_profile(std::ostream& os, const std::vector<KernelTime>& per_device, std::uint64_t steps,
                   std::size_t devices);

}  // namespace clsph::app
