// The time of one device's force pass, for the balancer, without the launch profiler (which the
// balancer used to force on, and which on rusticl times every launch by finishing the queue): a
// marker before the pass and one after it on the compute queue. Where the quirks layer says the
// device's event timestamps are honest, the markers' end timestamps give the time; elsewhere
// (rusticl's timestamps are fake) the host clock does: read in begin() once the queue is empty,
// and in the end marker's completion callback.
#pragma once
#include "cl/device.hpp"

#include <memory>

namespace clsph::multi {

class ForceTimer {
public:
    explicit ForceTimer(cl_rt::Device& device);
    void begin();  // enqueue before the force pass
    void end();    // and after it
    // The pass between the last begin() and end(), once the queue has run past end() (waits for
    // the callbacks where host clocks are used); 0 when nothing was timed.
    double seconds();

    struct Stamp;  // one marker's completion time, filled by its callback

private:
    cl_rt::Device& device_;
    bool host_clocks_;
    cl::Event begin_, end_;
    std::shared_ptr<Stamp> begin_stamp_, end_stamp_;
};

}  // namespace clsph::multi
