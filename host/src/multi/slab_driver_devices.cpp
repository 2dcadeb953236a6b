// Where the phases' work runs (each device of this rank on its own host thread where that helps)
// and, across ranks, giving the step up the moment a device fails (Ranks::give_up), so that the
// other ranks, and this rank's other threads, stop waiting for what it would have sent.
#include "multi/slab_driver.hpp"

#include "clsph/error.hpp"

#include <exception>
#include <mutex>

namespace clsph::multi {

StepOutcome SlabDriver::step(double dt, double time) {
    if (!across_ranks()) return step_here(dt, time);
    try {
        return step_here(dt, time);
    } catch (const RankFailure&) {
        throw;
    } catch (const std::exception& e) {
        ranks_.ranks->give_up(e.what());  // a failure on this thread (waiting for a device, say)
        throw;
    }
}

void SlabDriver::for_each_device(const PerDevice& work) {
    // One thread suffices where at most one device has anything to do (a GPU next to an idle CPU):
    // handing work to the other threads would only add their wake-ups to every phase.
    if (across_ranks()) {  // this rank's slabs, each on its own thread where it has several
        std::vector<std::size_t> mine;
        for (std::size_t d = 0; d < slabs_.size(); ++d)
            if (here(d)) mine.push_back(d);
        // A device failing gives the step up at once (Ranks::give_up): the other ranks, and this
        // rank's other threads, may be waiting for what it would have sent. Its error is the one
        // thrown, not a RankFailure another thread met because of it.
        std::exception_ptr failed;
        std::mutex first;
        const PerDevice guarded = [&](std::size_t d) {
            try {
                work(d);
            } catch (const RankFailure&) {
                throw;
            } catch (const std::exception& e) {
                {
                    std::lock_guard<std::mutex> lock(first);
                    if (!failed) failed = std::current_exception();
                }
                ranks_.ranks->give_up(e.what());
                throw;
            }
        };
        try {
            if (mine.size() == 1 || options_.seams.serialize_devices) {
                for (auto d : mine) guarded(d);
            } else if (!mine.empty()) {
                if (!threads_) threads_ = std::make_unique<DeviceThreads>(mine.size());
                threads_->run([&](std::size_t k) { guarded(mine[k]); });
            }
        } catch (...) {
            if (failed) std::rethrow_exception(failed);
            throw;
        }
        return;
    }
    std::size_t busy = 0;
    for (const auto& s : slabs_) busy += s.busy();
    if (slabs_.size() == 1 || options_.seams.serialize_devices || busy <= 1) {
        for (std::size_t d = 0; d < slabs_.size(); ++d) work(d);
        return;
    }
    if (!threads_) threads_ = std::make_unique<DeviceThreads>(slabs_.size());
    threads_->run(work);
}

}  // namespace clsph::multi
