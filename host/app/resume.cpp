#include "resume.hpp"

#include "interrupt.hpp"
#include "make_simulation.hpp"
#include "output_dir.hpp"
#include "run_ranks.hpp"

#include <clsph/checkpoint.hpp>
#include <clsph/error.hpp>
#include <clsph/io.hpp>
#include <clsph/ranks.hpp>

#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>

namespace clsph::app {
namespace {

std::string read_text_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw Error("cannot read " + path);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// The selection spec of `names` (labels "#i ...") without `failed`.
std::string remaining_devices(const std::vector<std::string>& names, const std::string& failed) {
    std::string spec;
    for (const auto& n : names) {
        if (n == failed || n.size() < 2 || n[0] != '#') continue;
        spec += (spec.empty() ? "" : ",") + n.substr(1, n.find(' ') - 1);
    }
    return spec;
}

// The newest checkpoint in the directory that reads back whole for this scene; the ones refused
// on the way are named with the reason.
std::pair<std::string, Checkpoint> latest_checkpoint(const std::string& dir, const Scene& scene) {
    const auto all = list_checkpoints(dir);
    std::string refused;
    for (auto it = all.rbegin(); it != all.rend(); ++it) {
        try {
            return {it->second, read_checkpoint(it->second, &scene)};
        } catch (const CheckpointError& e) {
            std::cerr << "clsph: refusing " << e.what() << '\n';
            refused += std::string(refused.empty() ? "" : "; ") + e.what();
        }
    }
    if (all.empty()) throw Error("clsph resume: no checkpoint (checkpoint_NNNNN.clsph) in " + dir);
    throw Error("clsph resume: no usable checkpoint in " + dir + " (" + refused + ")");
}

}  // namespace

namespace {

// Across ranks, once every rank has given up the step: fresh communicators, then every rank's
// failed device (if any) and devices left, gathered, so that every rank goes on alike. The devices
// left as a per-rank spec ("rank0=0;rank1=none": a rank with none takes part without slabs).
struct RanksLeft {
    std::string spec;
    std::string failed;  // "rank R: #i name failed: message", one line per failed device
    std::size_t devices = 0;
};

RanksLeft ranks_left(Ranks& ranks, const std::vector<std::string>& names, const LoopEnd& end) {
    recover(ranks);
    const std::string mine = remaining_devices(names, end.failed_device);
    std::size_t left = 0;
    for (const auto& n : names) left += n != end.failed_device;
    const std::string line = std::to_string(left) + " " + (mine.empty() ? "none" : mine) + "\n" +
                             (end.failed_device.empty() ? "" : "device " + end.failed_device + " failed: " + end.failure_message);
    RanksLeft out;
    const auto all = gather_text(ranks, line);
    for (std::size_t r = 0; r < all.size(); ++r) {
        const auto eol = all[r].find('\n');
        const std::string head = all[r].substr(0, eol), failure = all[r].substr(eol + 1);
        const auto space = head.find(' ');
        out.devices += std::stoul(head.substr(0, space));
        out.spec += (out.spec.empty() ? "" : ";") + ("rank" + std::to_string(r) + "=" + head.substr(space + 1));
        if (!failure.empty()) out.failed += (out.failed.empty() ? "" : "\n") + ("rank " + std::to_string(r) + ": " + failure);
    }
    return out;
}

}  // namespace

// With --on-device-failure continue, a device failure goes back to the last checkpoint on the
// devices that are left (as clsph resume would, recorded in run.json's resumes). Across ranks every
// rank gave up the step (the one whose device failed, and the others for it): every rank goes back
// to the same checkpoint, the slabs re-cut over the devices left on every rank.
int run_with_failover(Simulation& sim, const RunArgs& args, const RunPlan& plan, const ResumeState* state,
                      const Scene& scene, std::chrono::steady_clock::time_point start) {
    const std::vector<std::string> names = sim.device_names();
    const LoopEnd end = run_loop(sim, args, plan, state, start);
    if (!end.failed()) return end.code;
    RunArgs next = args;
    std::string failure = "device " + end.failed_device + " failed: " + end.failure_message;
    if (args.ranks && ranks_in(*args.ranks) > 1) {
        const RanksLeft left = ranks_left(*args.ranks, names, end);
        if (left.devices == 0)  // as in one process, the run cannot go on without a device
            abort_all(*args.ranks, exit_device_failed, "error: " + left.failed + "\nno device is left to go on with");
        next.devices = left.spec;
        failure = left.failed;
    } else {
        next.devices = remaining_devices(names, end.failed_device);
    }
    next.resume_dir = plan.out_dir;
    next.resume_reason = failure;
    next.resume_command_line = args.resume_command_line.empty() ? args.command_line : args.resume_command_line;
    if (speaks(args))
        std::cerr << "clsph: " << failure << "\nclsph: --on-device-failure continue: going back to the last checkpoint on devices "
                  << next.devices << '\n';
    // The test build (clsph-faulty): the injected fault was the failure; the devices left run clean.
    next.test_seams = false;
    return resume_run(scene, next, plan, start);
}

int resume_run(const Scene& scene, const RunArgs& args, const RunPlan& plan, std::chrono::steady_clock::time_point start) {
    auto [path, checkpoint] = latest_checkpoint(plan.out_dir, scene);
    ResumeState state;
    state.point = {checkpoint.step, checkpoint.time};
    state.frames = read_pvd(plan.out_dir + "/" + plan.collection_name);
    nlohmann::json old;
    try {
        old = nlohmann::json::parse(read_text_file(plan.out_dir + "/run.json"));
    } catch (const std::exception& e) {
        throw Error("clsph resume: cannot read " + plan.out_dir + "/run.json: " + e.what());
    }
    state.start_time = old.value("start_time", std::string());
    if (old.contains("resumes"))
        for (const auto& r : old.at("resumes")) state.resumes.push_back(r.dump());
    install_interrupt_handler();
    std::unique_ptr<Simulation> simulation = make_simulation(scene, args, &checkpoint);
    Simulation& sim = *simulation;
    const auto names = all_device_names(sim, args);
    nlohmann::json entry{{"command_line", args.resume_command_line}, {"checkpoint", path},
                         {"step", checkpoint.step},   {"time", checkpoint.time},
                         {"devices", names}, {"at", utc_now()}};
    if (!args.resume_reason.empty()) entry["reason"] = args.resume_reason;
    state.resumes.push_back(entry.dump());
    if (speaks(args)) {
        std::cout << "clsph: resuming " << plan.out_dir << " from " << path << " (step " << checkpoint.step << ", t = "
                  << checkpoint.time << " s) on";
        for (const auto& d : names) std::cout << (args.ranks ? "\n  " : " ") << d;
        std::cout << (args.ranks ? "\n  " : ", ") << "to t = " << plan.until << " s" << std::endl;
    }
    return run_with_failover(sim, args, plan, &state, scene, start);
}

}  // namespace clsph::app
