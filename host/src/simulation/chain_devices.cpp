// The devices a run's chain of slabs spans (clsph/memory_plan.hpp, chain_devices): across MPI
// ranks every rank's own devices, gathered from every rank in rank order, so that every rank
// plans the memory of the whole chain alike and checks its own devices and slabs in it.
#include "simulation/chain_devices.hpp"

#include "clsph/error.hpp"
#include "clsph/testing.hpp"
#include "multi/rank_devices.hpp"
#include "multi/ranks.hpp"

#include <cstring>

namespace clsph {
namespace {

void put_text(std::string& out, const std::string& s) {
    const std::uint64_t n = s.size();
    out.append(reinterpret_cast<const char*>(&n), 8);
    out += s;
}
void put_word(std::string& out, std::uint64_t w) { out.append(reinterpret_cast<const char*>(&w), 8); }

struct Reader {
    const std::string& in;
    std::size_t at = 0;
    std::uint64_t word() {
        if (in.size() - at < 8) throw Error("the devices of the ranks: a rank's list is malformed");
        std::uint64_t w = 0;
        std::memcpy(&w, in.data() + at, 8);
        at += 8;
        return w;
    }
    std::string text() {
        const std::uint64_t n = word();
        if (in.size() - at < n) throw Error("the devices of the ranks: a rank's list is malformed");
        std::string s = in.substr(at, static_cast<std::size_t>(n));
        at += static_cast<std::size_t>(n);
        return s;
    }
};

std::string encode(const std::vector<DeviceInfo>& infos) {
    std::string out;
    for (const auto& d : infos) {
        put_word(out, d.index);
        for (const auto* s : {&d.platform, &d.vendor, &d.name, &d.type, &d.driver_version, &d.opencl_c_version}) put_text(out, *s);
        for (std::uint64_t w : {std::uint64_t{d.compute_units}, d.global_memory, d.max_allocation, d.local_memory,
                                std::uint64_t{d.max_work_group_size}, std::uint64_t{d.fp64}})
            put_word(out, w);
    }
    return out;
}

std::vector<DeviceInfo> decode(const std::string& in) {
    std::vector<DeviceInfo> out;
    Reader r{in};
    while (r.at < in.size()) {
        DeviceInfo d;
        d.index = static_cast<std::size_t>(r.word());
        for (auto* s : {&d.platform, &d.vendor, &d.name, &d.type, &d.driver_version, &d.opencl_c_version}) *s = r.text();
        d.compute_units = static_cast<std::uint32_t>(r.word());
        d.global_memory = r.word();
        d.max_allocation = r.word();
        d.local_memory = r.word();
        d.max_work_group_size = static_cast<std::size_t>(r.word());
        d.fp64 = r.word() != 0;
        out.push_back(d);
    }
    return out;
}

}  // namespace

namespace simulation {

std::string rank_spec(const std::string& spec, const Ranks& ranks) {
    std::string mine;
    for (auto i : multi::rank_devices(list_devices(), spec, ranks.place()))
        mine += (mine.empty() ? "" : ",") + std::to_string(i);
    return mine;
}

ChainDevices chain_devices(const std::string& spec, const cl_rt::OpenOptions& open, Ranks* ranks) {
    ChainDevices c;
    if (!ranks) {
        c.devices = cl_rt::selected_infos(spec, open);
        c.rank.assign(c.devices.size(), 0);
        c.end = c.devices.size();
        return c;
    }
    const std::string mine = rank_spec(spec, *ranks);  // empty: this rank drives none ('rankN=none')
    const auto all = ranks->gather_text(encode(mine.empty() ? std::vector<DeviceInfo>{} : cl_rt::selected_infos(mine, open)));
    for (std::size_t r = 0; r < all.size(); ++r) {
        const auto infos = decode(all[r]);
        if (static_cast<int>(r) == ranks->rank()) {
            c.first = c.devices.size();
            c.end = c.first + infos.size();
        }
        c.devices.insert(c.devices.end(), infos.begin(), infos.end());
        c.rank.insert(c.rank.end(), infos.size(), static_cast<int>(r));
    }
    return c;
}

}  // namespace simulation

ChainDevices chain_devices(const Options& options) {
    cl_rt::OpenOptions open;
    if (options.seams) open.max_allocation = options.seams->max_allocation;
    return simulation::chain_devices(options.devices.empty() ? default_device_spec() : options.devices, open,
                                     options.ranks.get());
}

}  // namespace clsph
