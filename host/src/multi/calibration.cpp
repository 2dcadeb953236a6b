#include "multi/calibration.hpp"

#include <algorithm>
#include <array>

namespace clsph::multi {

void calibrate(std::vector<Slab>& slabs, const Partition& partition, const ColumnSampler& sample, std::size_t total_count,
               const Census& census, balance::Balancer& balancer) {
    // Samples are whole columns around the column that halves the work (so they look like the
    // scene: the same neighbour counts, fluid and walls), growing 4x per round from 4096 particles
    // until a device's force pass takes 20 ms, or the sample is the whole scene (at most 4 M
    // particles), or the next would outgrow the device's store (calibrating never raises the
    // memory peak). The last two rounds give fixed + per-unit cost: a GPU is timed at sizes that
    // fill it, a CPU stops early. Set-up cost: about 2 x (the largest round) per device.
    const std::size_t columns = partition.columns();
    const auto& work = census.profile.work;
    const auto& count = census.profile.particles;
    double total = 0;
    for (double w : work) total += w;
    std::size_t mid = 0;
    for (double acc = 0; mid + 1 < columns && acc + work[mid] < 0.5 * total; ++mid) acc += work[mid];
    auto sample_of = [&](std::size_t want, double& sampled) {
        std::size_t lo = mid, hi = mid, n = 0;
        sampled = 0;
        while (n < want && (lo > 0 || hi < columns)) {
            const bool right = hi < columns && (lo == 0 || hi - mid <= mid - lo);
            const std::size_t c = right ? hi++ : --lo;
            n += count[c];
            sampled += work[c];
        }
        return sample(lo, hi);
    };
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        Slab& s = slabs[d];
        if (!s.device) continue;  // across ranks: another rank's, timed there
        // The test slowdown (testing.hpp) is left out on purpose: it stands for a device that
        // becomes slow after the start, which the dynamic balancer must notice by itself.
        std::vector<std::array<double, 2>> points;  // (work, seconds)
        std::size_t previous = 0;
        for (std::size_t want = std::min<std::size_t>(total_count, 4096);; want *= 4) {
            double sampled = 0;
            const Particles taken = sample_of(want, sampled);
            if (taken.size() == previous) break;  // the whole scene already
            // No sample larger than the device's store after the first: calibrating does not
            // grow the store beyond what the run gives it (the memory plan's peak holds).
            if (previous > 0 && taken.size() > s.store->capacity()) break;
            previous = taken.size();
            s.store->upload(taken);
            s.cells->run(*s.store);
            double seconds = 0;
            for (int round = 0; round < 2; ++round) {  // the first compiles and warms up
                s.force_timer->begin();
                s.physics->forces(*s.store, *s.cells, s.store->scratch);
                s.force_timer->end();
                s.device->finish();
                seconds = s.force_timer->seconds();
            }
            if (sampled > 0 && seconds > 0) points.push_back({sampled, seconds});
            if (taken.size() >= total_count || want >= (std::size_t{1} << 22) || (points.size() >= 2 && seconds >= 0.02)) break;
        }
        if (points.empty()) continue;
        const auto& b = points.back();
        double per_unit = b[1] / b[0], fixed = 0;
        if (points.size() >= 2) {
            const auto& a = points[points.size() - 2];
            const double slope = (b[1] - a[1]) / (b[0] - a[0]);
            if (slope > 0 && b[0] > a[0] && b[1] - slope * b[0] >= 0) {
                per_unit = slope;
                fixed = b[1] - slope * b[0];
            }
        }
        balancer.calibrate(d, fixed, per_unit);
        s.calibration = {fixed, per_unit, total};
    }
}

void share_calibrations(std::vector<Slab>& slabs, Ranks& ranks, balance::Balancer& balancer) {
    // (calibrated, fixed, per unit, work) per slab: one rank's figures and the others' zeros, so
    // the sums are exact.
    std::vector<double> v(4 * slabs.size(), 0.0);
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        const auto& c = slabs[d].calibration;
        if (!slabs[d].device || c.work_total == 0) continue;
        v[4 * d] = 1;
        v[4 * d + 1] = c.fixed;
        v[4 * d + 2] = c.per_unit;
        v[4 * d + 3] = c.work_total;
    }
    ranks.sum(v);
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        if (slabs[d].device || v[4 * d] == 0) continue;
        balancer.calibrate(d, v[4 * d + 1], v[4 * d + 2]);
        slabs[d].calibration = {v[4 * d + 1], v[4 * d + 2], v[4 * d + 3]};
    }
}

}  // namespace clsph::multi
