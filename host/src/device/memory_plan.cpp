// The memory model (clsph/memory_plan.hpp): the census of the scene (memory_census.cpp), its split
// over the slabs (memory_split.cpp) and each slab's buffers (memory_buffers.cpp), sized by the
// rules the allocations use (device/sizing.hpp); here the slab count per device, the plan's sums
// and the error of a scene that does not fit. Pure C++.
#include "clsph/memory_plan.hpp"

#include "clsph/error.hpp"
#include "clsph/testing.hpp"
#include "device/memory_census.hpp"
#include "device/memory_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>

namespace clsph {

std::size_t DeviceMemoryPlan::total_bytes() const {
    std::size_t b = 0;
    for (const auto& x : buffers) b += x.bytes;
    return b;
}

std::size_t DeviceMemoryPlan::scaling_bytes() const {
    std::size_t b = 0;
    for (const auto& x : buffers) b += x.scales ? x.bytes : 0;
    return b;
}

const PlannedBuffer& DeviceMemoryPlan::largest() const {
    static const PlannedBuffer none;
    if (buffers.empty()) return none;
    return *std::max_element(buffers.begin(), buffers.end(),
                             [](const PlannedBuffer& a, const PlannedBuffer& b) { return a.bytes < b.bytes; });
}

bool DeviceMemoryPlan::fits() const {
    return (device.global_memory == 0 || total_bytes() <= device.global_memory) &&
           (device.max_allocation == 0 || largest().bytes <= device.max_allocation);
}

namespace {
// The entries [first, end) of the device that entry d is a slab of.
std::pair<std::size_t, std::size_t> slabs_of(const MemoryPlan& plan, std::size_t d) {
    const std::size_t first = d - plan.devices.at(d).slab;
    return {first, std::min(plan.devices.size(), first + plan.devices[d].slabs)};
}
}  // namespace

std::size_t MemoryPlan::device_bytes(std::size_t d) const {
    const auto [first, end] = slabs_of(*this, d);
    std::size_t b = 0;
    for (std::size_t k = first; k < end; ++k) b += devices[k].total_bytes();
    return b;
}

std::vector<std::size_t> MemoryPlan::slabs_per_device() const {
    std::vector<std::size_t> out;
    for (const auto& x : devices)
        if (x.slab == 0) out.push_back(x.slabs);
    return out;
}

std::size_t MemoryPlan::largest_particles(std::size_t d) const {
    // The device's slabs together: their scaling bytes grow with the scene, their fixed ones do not.
    // A buffer that would outgrow one allocation means one more slab (a few fixed bytes), not a limit.
    const auto [first, end] = slabs_of(*this, d);
    std::size_t scaling = 0, fixed = 0;
    for (std::size_t k = first; k < end; ++k) {
        scaling += devices[k].scaling_bytes();
        fixed += devices[k].fixed_bytes();
    }
    const double per = scaling ? static_cast<double>(scaling) / static_cast<double>(particles) : 0.0;
    const double room = static_cast<double>(devices[d].device.global_memory) - static_cast<double>(fixed);
    if (per <= 0 || room <= 0) return 0;
    return static_cast<std::size_t>(room / per);
}

std::size_t MemoryPlan::largest_particles() const {
    std::size_t n = devices.empty() ? 0 : SIZE_MAX;
    for (std::size_t d = 0; d < devices.size(); ++d) n = std::min(n, largest_particles(d));
    return n;
}

double MemoryPlan::dp_for(std::size_t n) const {
    if (n == 0 || particles == 0) return 0;
    return dp * std::cbrt(static_cast<double>(particles) / static_cast<double>(n));
}

bool MemoryPlan::fits() const {
    for (std::size_t d = 0; d < devices.size(); ++d) {
        const auto& x = devices[d];
        if (!x.fits()) return false;
        if (x.slab == 0 && x.device.global_memory && device_bytes(d) > x.device.global_memory) return false;
    }
    return true;
}

MemoryPlan plan_memory(const Scene& scene, const Particles& p, const std::vector<DeviceInfo>& devices,
                       const Options& options) {
    return detail::plan_memory(scene, detail::census_of(scene, p), devices, options);
}

MemoryPlan plan_memory(const Scene& scene, const std::vector<DeviceInfo>& devices, const Options& options) {
    if (options.setup_on_device && scene::LatticePlan::supports(scene))
        return detail::plan_memory(scene, detail::census_of(scene, scene::LatticePlan::make(scene)), devices, options);
    return plan_memory(scene, scene.build_particles(), devices, options);
}

namespace detail {

constexpr std::size_t most_slabs = 64;  // per device

namespace {
MemoryPlan plan_form(const Scene& scene, const MemoryCensus& census, const std::vector<DeviceInfo>& devices,
                     const Options& options);
}  // namespace

MemoryPlan plan_memory(const Scene& scene, const MemoryCensus& census, const std::vector<DeviceInfo>& devices,
                       const Options& options) {
    // The clusters form's lists where they fit; where not, the list-free fine form (the largest
    // scene a device runs does not shrink for them).
    const Interaction asked = options.interaction != Interaction::automatic ? options.interaction : scene.run.interaction;
    MemoryPlan plan = plan_form(scene, census, devices, options);
    plan.interaction = asked;
    if (asked != Interaction::clusters || plan.fits()) return plan;
    Options fine = options;
    fine.interaction = Interaction::fine;
    MemoryPlan without = plan_form(scene, census, devices, fine);
    if (!without.fits()) return plan;
    without.interaction = Interaction::fine;
    without.notes.push_back("the clusters interaction form's lists would not fit: the run takes the fine form");
    return without;
}

namespace {
MemoryPlan plan_form(const Scene& scene, const MemoryCensus& census, const std::vector<DeviceInfo>& devices,
                     const Options& options) {
    // One slab per device, then one more at a time on the devices where a slab's largest buffer
    // exceeds the largest allocation (the cuts move with the slab count, so plan again). Slabs
    // hold their neighbours' halo columns too, so on a narrow domain more slabs stop helping: a
    // device whose worst slab has not shrunk in three tries keeps its count (and does not fit).
    const std::size_t at_least = options.seams && options.seams->slabs > 1 ? options.seams->slabs : 1;
    std::vector<std::size_t> slabs(devices.size(), at_least), stalled(devices.size(), 0);
    std::vector<double> best(devices.size(), 0.0);
    for (;;) {
        std::vector<DeviceInfo> expanded;
        for (std::size_t i = 0; i < devices.size(); ++i) expanded.insert(expanded.end(), slabs[i], devices[i]);
        MemoryPlan plan = plan_slabs(scene, census, expanded, options);
        bool more = false;
        std::size_t at = 0;
        for (std::size_t i = 0; i < devices.size(); ++i) {
            double worst = 0;  // the largest buffer of the device's slabs over one allocation
            for (std::size_t k = 0; k < slabs[i]; ++k) {
                auto& x = plan.devices.at(at + k);
                x.slab = k;
                x.slabs = slabs[i];
                if (devices[i].max_allocation)
                    worst = std::max(worst, static_cast<double>(x.largest().bytes) / static_cast<double>(devices[i].max_allocation));
            }
            at += slabs[i];
            if (worst <= 1.0) continue;
            if (slabs[i] == at_least || worst < best[i]) {
                best[i] = worst;
                stalled[i] = 0;
            } else {
                ++stalled[i];
            }
            if (stalled[i] < 3 && slabs[i] < most_slabs) {
                ++slabs[i];
                more = true;
            }
        }
        if (more) continue;
        for (std::size_t i = 0; i < devices.size(); ++i)
            if (slabs[i] > 1)
                plan.notes.push_back("device #" + std::to_string(devices[i].index) + " " + devices[i].name + " runs as " +
                                     std::to_string(slabs[i]) +
                                     " slabs: one slab's buffers would exceed its CL_DEVICE_MAX_MEM_ALLOC_SIZE (" +
                                     std::to_string(devices[i].max_allocation) + " bytes)");
        return plan;
    }
}
}  // namespace

}  // namespace detail

void check_fits(const MemoryPlan& plan) {
    if (plan.fits()) return;
    char text[512];
    std::snprintf(text, sizeof text, "physics.dp = %g: the scene needs %zu particles (%.3g)", plan.dp, plan.particles,
                  static_cast<double>(plan.particles));
    std::string msg = text;
    const double gib = 1024.0 * 1024.0 * 1024.0;
    for (std::size_t i = 0; i < plan.devices.size(); ++i) {
        const auto& d = plan.devices[i];
        if (d.slab != 0) continue;
        std::snprintf(text, sizeof text, "; %.3g GiB on device '%s' which has %.3g GiB",
                      static_cast<double>(plan.device_bytes(i)) / gib, d.device.name.c_str(),
                      static_cast<double>(d.device.global_memory) / gib);
        msg += text;
        if (d.slabs > 1) msg += " (as " + std::to_string(d.slabs) + " slabs)";
        const auto& big = d.largest();
        if (d.device.max_allocation && big.bytes > d.device.max_allocation) {
            std::snprintf(text, sizeof text, " (its largest buffer, '%s', needs %.3g GiB but one allocation may be at most %.3g GiB)",
                          big.name.c_str(), static_cast<double>(big.bytes) / gib,
                          static_cast<double>(d.device.max_allocation) / gib);
            msg += text;
        }
    }
    const std::size_t n = plan.largest_particles();
    if (n > 0) {
        std::snprintf(text, sizeof text, ". At most about %zu particles fit these devices: physics.dp >= %.3g", n, plan.dp_for(n));
        msg += text;
    }
    throw SceneError(msg + " (clsph run --dry-run prints the memory plan)");
}

}  // namespace clsph
