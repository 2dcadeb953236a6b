#include "simulation/downloads.hpp"

#include "cl/errors.hpp"

#include <cmath>
#include <exception>
#include <thread>

namespace clsph::simulation {
namespace {

// The devices keep density only; pressure follows from it by the equation of state (Tait, gamma 7).
void fill_pressure(Particles& p, const SphParams& sp) {
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x = p.density[i] / sp.rho0;
        p.pressure[i] = static_cast<float>(sp.eos_b * (std::pow(x, 7.0) - 1.0));
    }
}

Particles concatenated(const std::vector<Particles>& pieces) {
    Particles all;
    for (const auto& p : pieces)
        for (std::size_t i = 0; i < p.size(); ++i)
            all.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
    return all;
}

}  // namespace

void Downloads::keep(Particles p) {
    last_good_ = std::move(p);
    state_.last_good_time = state_.info.time;
}

Particles Downloads::all() {
    Particles p = cl_rt::guarded("downloading the particles", "", [&] { return driver_.download(); });
    fill_pressure(p, driver_.params());
    keep(p);
    return p;
}

std::vector<Particles> Downloads::by_device(const ParticleSelection& which) {
    auto& slabs = driver_.slabs();
    // Across ranks: this rank's slabs (the others' pieces are theirs to write).
    std::vector<std::size_t> here;
    for (std::size_t d = 0; d < slabs.size(); ++d)
        if (driver_.here(d)) here.push_back(d);
    std::vector<Particles> pieces(slabs.size());
    auto download = [&](std::size_t k) {
        pieces[k] = cl_rt::guarded("downloading the particles", slabs[k].device->label(), [&] {
            return which.all() ? slabs[k].store->download() : driver_.download_every(k, which.stride, which.box);
        });
        fill_pressure(pieces[k], driver_.params());
    };
    if (here.size() == 1) {
        download(here[0]);
    } else {
        // Each device's read waits on its own queue: one thread per device, so they overlap.
        std::vector<std::exception_ptr> errors(slabs.size());
        std::vector<std::thread> threads;
        for (std::size_t k : here)
            threads.emplace_back([&, k] {
                try {
                    download(k);
                } catch (...) {
                    errors[k] = std::current_exception();
                }
            });
        for (auto& t : threads) t.join();
        for (const auto& e : errors)
            if (e) std::rethrow_exception(e);
    }
    if (driver_.across_ranks()) {
        std::vector<Particles> mine;
        for (auto k : here) mine.push_back(std::move(pieces[k]));
        return mine;  // (a rank's part is no state to go back to)
    }
    if (!which.all()) return pieces;  // a thinned state is no state to go back to
    keep(concatenated(pieces));
    return pieces;
}

Particles Downloads::selected(const ParticleSelection& which) {
    if (which.all()) return all();
    return concatenated(by_device(which));
}

const Particles& Downloads::last_good() {
    // Set up on the devices and nothing downloaded yet: the last good state is the scene's start,
    // built on the host only now that it is asked for.
    if (last_good_.size() == 0 && plan_) last_good_ = plan_->particles();
    return last_good_;
}

}  // namespace clsph::simulation
