// When the cell tables and cluster lists are built again, with run.list_buffer (docs/interaction.md,
// "Lists kept over steps"). Cells are the buffer wider than the support, so tables built at one
// set of positions hold every pair within the support for as long as no particle has moved more
// than half the buffer since: two particles within the support now were then within the support
// plus the buffer, hence in neighbouring rows. The leap-frog drift moves a fluid particle by
// (v_n + a_n dt / 2) dt, so max |v_n| and max |a_n|, which the last step's reductions gave, bound
// every particle's move before the step runs; the bounds add up from build to build. Pure C++.
#pragma once
#include <cstddef>

namespace clsph::multi {

class ListSchedule {
public:
    // half_buffer: half the margin, m (0: tables built every step).
    explicit ListSchedule(double half_buffer = 0) : half_buffer_(half_buffer) {}
    bool on() const { return half_buffer_ > 0; }
    double half_buffer() const { return half_buffer_; }
    // Before a step of dt: whether the tables must be built after its drift, from the largest
    // squared speed and acceleration the last step's reductions gave (any particle may move by
    // at most (|v| + |a| dt / 2) dt). Call built() or kept() after it, as the step went.
    bool due(double dt, double max_speed2, double max_accel2) const;
    void built() { moved_ = 0, ++builds_, age_ = 0; }  // also the first tables, before the first step
    void kept(double dt, double max_speed2, double max_accel2) { moved_ += bound(dt, max_speed2, max_accel2), ++age_; }
    double moved() const { return moved_; }    // the bound on any particle's move since the last build, m
    // moved() after a kept step of dt (what kept() will make it).
    double moved_after(double dt, double max_speed2, double max_accel2) const {
        return moved_ + bound(dt, max_speed2, max_accel2);
    }
    // A guess, for the steps ahead of the host: whether `steps` more kept steps of dt, each moving
    // up to `margin` times what the last one's reductions allow, would still keep the tables.
    // The host enqueues no further step ahead once this is false (every device halts a step that
    // must build, and the steps in flight behind it are computed for nothing), and takes the last
    // kept steps one at a time: the guess changes no result, only how far ahead steps run.
    bool likely_kept(std::size_t steps, double dt, double max_speed2, double max_accel2, double margin) const {
        return moved_ + static_cast<double>(steps) * margin * bound(dt, max_speed2, max_accel2) < half_buffer_;
    }
    std::size_t builds() const { return builds_; }  // since the start (the first tables included)
    std::size_t age() const { return age_; }          // steps since the last build

private:
    static double bound(double dt, double max_speed2, double max_accel2);
    double half_buffer_;
    double moved_ = 0;
    std::size_t builds_ = 0, age_ = 0;
};

}  // namespace clsph::multi
