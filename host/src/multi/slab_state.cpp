// What a checkpoint holds of the slabs (SlabDriver::save_owned, restore_owned): each slab's owned
// arrays, read and written by one pair of loops (owned_arrays), in slab order whichever rank holds
// them.
#include "multi/slab_driver.hpp"

#include "clsph/error.hpp"
#include "multi/ranks.hpp"

#include <algorithm>
#include <cstring>
#include <unordered_map>
#include <utility>

namespace clsph::multi {
namespace {

// Where one slab's owned particles go or come from: the four arrays a checkpoint keeps.
struct OwnedArrays {
    float* pos;
    float* velrho;
    float* accel;
    std::uint32_t* id;
};

void read_owned(Slab& s, const OwnedArrays& to) {
    auto& st = *s.store;
    const std::size_t n = st.ranges.owned, first = st.ranges.first_owned();
    if (n == 0) return;
    s.device->read(st.pos, to.pos, 4 * n, 4 * first);
    s.device->read(st.velrho, to.velrho, 4 * n, 4 * first);
    s.device->read(st.accel, to.accel, 4 * n, 4 * first);
    s.device->read(st.id, to.id, n, first);
}

void write_owned(Slab& s, const OwnedArrays& from) {
    auto& st = *s.store;
    const std::size_t n = st.ranges.owned, first = st.ranges.first_owned();
    if (n == 0) return;
    s.device->write(st.pos, from.pos, 4 * n, 4 * first);
    s.device->write(st.velrho, from.velrho, 4 * n, 4 * first);
    s.device->write(st.accel, from.accel, 4 * n, 4 * first);
    s.device->write(st.id, from.id, n, first);
    s.device->finish();
}

// Room for the next slab's n particles at the end of c's arrays (its count recorded).
OwnedArrays grow_for_slab(Checkpoint& c, std::size_t n) {
    const std::size_t at = c.size();
    c.counts.push_back(n);
    c.pos.resize(4 * (at + n));
    c.velrho.resize(4 * (at + n));
    c.accel.resize(4 * (at + n));
    c.id.resize(at + n);
    return {c.pos.data() + 4 * at, c.velrho.data() + 4 * at, c.accel.data() + 4 * at, c.id.data() + at};
}

}  // namespace

void SlabDriver::save_owned(Checkpoint& c) {
    if (bodies_)  // the host's: the same on every rank
        for (const auto& b : bodies_->states()) b.save(c.bodies);
    if (!across_ranks()) {
        for (auto& s : slabs_) read_owned(s, grow_for_slab(c, s.store->ranges.owned));
        return;
    }
    // Across ranks: each rank's slabs as bytes (slab, count, then the four arrays), gathered on
    // rank 0 (which writes the file) and laid out in slab order: the file one process on as many
    // devices would write. The other ranks send theirs and keep no particles.
    std::string mine;
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        if (!here(d)) continue;
        const std::uint64_t n = slabs_[d].store->ranges.owned, slab = d;
        const std::size_t at = mine.size() + 16;
        mine.resize(at + 52 * n);
        std::memcpy(&mine[at - 16], &slab, 8);
        std::memcpy(&mine[at - 8], &n, 8);
        char* p = &mine[0] + at;
        read_owned(slabs_[d], {reinterpret_cast<float*>(p), reinterpret_cast<float*>(p + 16 * n),
                               reinterpret_cast<float*>(p + 32 * n), reinterpret_cast<std::uint32_t*>(p + 48 * n)});
    }
    struct Part { const char* at; std::uint64_t n; };
    std::vector<Part> parts(slabs_.size(), Part{nullptr, 0});
    const auto all = ranks_.ranks->gather_text_to(std::move(mine), 0);
    if (ranks_.rank != 0) return;
    for (const auto& r : all)
        for (std::size_t k = 0; k + 16 <= r.size();) {
            std::uint64_t slab = 0, n = 0;
            std::memcpy(&slab, r.data() + k, 8);
            std::memcpy(&n, r.data() + k + 8, 8);
            if (slab >= parts.size() || r.size() - k - 16 < 52 * n) throw Error("checkpoint across ranks: a rank's part is malformed");
            parts[slab] = {r.data() + k + 16, n};
            k += 16 + 52 * n;
        }
    for (const auto& part : parts) {
        const std::size_t n = part.n;
        const OwnedArrays to = grow_for_slab(c, n);
        if (n == 0) continue;
        std::memcpy(to.pos, part.at, 16 * n);
        std::memcpy(to.velrho, part.at + 16 * n, 16 * n);
        std::memcpy(to.accel, part.at + 32 * n, 16 * n);
        std::memcpy(to.id, part.at + 48 * n, 4 * n);
    }
}

void SlabDriver::restore_owned(const Checkpoint& c) {
    // The first pass sorted the decoded particles; the checkpoint's arrays go over the owned ones.
    // Written on this device count with the same split, each slab holds its block of the file in
    // its order: the arrays go in as they are, ids included (a particle on a cell face may have
    // sorted elsewhere in the first pass, its position decoded and encoded again, while the file's
    // block is the slab's sorted order as saved; the cell tables follow at the next exchange,
    // before any force pass). Otherwise by id: the positions as this device's first pass encoded
    // them (the key decided the order the slab sorted), velocity, density and the last forces as
    // saved. Across ranks each rank restores its own slabs (its block of the file starts after the
    // blocks of the slabs before it, whichever rank holds them).
    if (bodies_) {
        if (c.bodies.size() != bodies_->size() * BodyState::kDoubles)
            throw Error("restoring a checkpoint: it holds " + std::to_string(c.bodies.size() / BodyState::kDoubles) +
                        " floating bodies' states, the scene has " + std::to_string(bodies_->size()));
        std::vector<BodyState> states;
        for (std::size_t b = 0; b < bodies_->size(); ++b) states.push_back(BodyState::load(c.bodies.data() + b * BodyState::kDoubles));
        bodies_->set_states(states);
    }
    bool same = c.counts.size() == slabs_.size();
    for (std::size_t d = 0; same && d < slabs_.size(); ++d) same = !here(d) || slabs_[d].store->ranges.owned == c.counts[d];
    std::unordered_map<std::uint32_t, std::size_t> index;
    if (!same)
        for (std::size_t i = 0; i < c.size(); ++i) index[c.id[i]] = i;
    std::size_t from = 0;
    for (std::size_t d = 0; d < slabs_.size(); ++d) {
        if (!here(d)) {
            if (same) from += c.counts[d];
            continue;
        }
        auto& s = slabs_[d];
        const std::size_t n = s.store->ranges.owned;
        if (n == 0) continue;
        std::vector<float> pos(4 * n), velrho(4 * n), accel(4 * n);
        std::vector<std::uint32_t> ids(n);
        if (same) {
            std::copy_n(c.pos.begin() + 4 * from, 4 * n, pos.begin());
            std::copy_n(c.velrho.begin() + 4 * from, 4 * n, velrho.begin());
            std::copy_n(c.accel.begin() + 4 * from, 4 * n, accel.begin());
            std::copy_n(c.id.begin() + from, n, ids.begin());
            from += n;
        } else {
            read_owned(s, {pos.data(), velrho.data(), accel.data(), ids.data()});
            for (std::size_t i = 0; i < n; ++i) {
                const auto it = index.find(ids[i]);
                if (it == index.end()) throw Error("restoring a checkpoint: a particle id not in it");
                const std::size_t j = it->second;
                std::copy_n(c.velrho.begin() + 4 * j, 4, velrho.begin() + 4 * i);
                std::copy_n(c.accel.begin() + 4 * j, 4, accel.begin() + 4 * i);
            }
        }
        write_owned(s, {pos.data(), velrho.data(), accel.data(), ids.data()});
    }
}

}  // namespace clsph::multi
