// The time of one device's force pass, for the balancer, without the launch profiler (which the
// balancer used to force on, and which on rusticl times every launch by finishing the queue): a
// marker before the pass and one after it on the compute queue. Where the quirks layer says the
// device's event timestamps are honest, the markers' end timestamps give the time; elsewhere
// (rusticl's timestamps are fake) the host clock does: read in begin() once the queue is empty,
// and in the end marker's completion callback.
#pragma once
#include "cl/device.hpp"

#include <memory>
#include <vector>

namespace clsph::multi {

class ForceTimer {
public:
    explicit ForceTimer(cl_rt::Device& device);
    // Enqueue before the force pass: a new pass (what was timed before and not read is dropped, as
    // the first pass of a Symplectic step), or with `more` a further part of the same pass (a pass
    // split around the halo: the interior, then the rest).
    void begin(bool more = false);
    void end();  // and after it (or the part)
    // The pass: the sum of its parts, once the queue has run past the last end() (waits for the
    // callbacks where host clocks are used); 0 when nothing was timed.
    double seconds();

    struct Stamp;  // one marker's completion time, filled by its callback

private:
    struct Part {
        cl::Event begin, end;
        std::shared_ptr<Stamp> begin_stamp, end_stamp;
    };
    cl_rt::Device& device_;
    bool host_clocks_;
    std::vector<Part> parts_;
};

}  // namespace clsph::multi
