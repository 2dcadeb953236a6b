// The checkpoint file (docs/checkpoint.md): little-endian, fixed layout, FNV-1a 64 checksum last.
#include "clsph/checkpoint.hpp"

#include "clsph/version.hpp"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace clsph {

namespace {

constexpr char kMagic[8] = {'C', 'L', 'S', 'P', 'H', 'C', 'K', 'P'};
// The inlets block's first word (write_checkpoint): "INLETS" and two zero bytes, little-endian.
constexpr std::uint64_t kInletTag = 0x00005354454c4e49ull;

std::uint64_t fnv1a(const unsigned char* p, std::size_t n, std::uint64_t h = 1469598103934665603ull) {
    for (std::size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

struct Writer {
    std::string out;
    void raw(const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); }
    template <class T>
    void put(T v) { raw(&v, sizeof v); }
    template <class T>
    void vec(const std::vector<T>& v) { raw(v.data(), v.size() * sizeof(T)); }
};

struct Reader {
    const std::string& in;
    const std::string& path;
    std::size_t at = 0;
    void raw(void* p, std::size_t n) {
        if (in.size() - at < n) throw CheckpointError(path, "truncated (the file ends early: " + std::to_string(in.size()) + " bytes)");
        std::memcpy(p, in.data() + at, n);
        at += n;
    }
    template <class T>
    T get() {
        T v{};
        raw(&v, sizeof v);
        return v;
    }
    template <class T>
    void vec(std::vector<T>& v, std::uint64_t n) {
        if (n > (in.size() - at) / sizeof(T)) throw CheckpointError(path, "truncated (the particle arrays end early)");
        v.resize(n);
        raw(v.data(), n * sizeof(T));
    }
};

}  // namespace

std::uint64_t scene_hash(const Scene& scene) {
    Scene s = scene;
    s.run.end_time = 0;
    const std::string j = s.to_json();
    return fnv1a(reinterpret_cast<const unsigned char*>(j.data()), j.size());
}

void write_checkpoint(const std::string& path, const Checkpoint& c) {
    Writer w;
    w.raw(kMagic, sizeof kMagic);
    w.put<std::uint32_t>(c.format);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(c.clsph_version.size()));
    w.raw(c.clsph_version.data(), c.clsph_version.size());
    w.put(c.scene_hash);
    w.put(c.step);
    w.put(c.time);
    w.put(c.dt);
    w.put(c.dt_next);
    w.put(c.removed);
    w.put(c.fluid);
    w.put(c.cells);
    w.put(c.kinetic_energy);
    w.put(c.max_speed);
    w.put<std::uint64_t>(c.counts.size());
    w.vec(c.cuts);
    w.vec(c.counts);
    w.put<std::uint64_t>(c.size());
    w.vec(c.pos);
    w.vec(c.velrho);
    w.vec(c.accel);
    w.vec(c.id);
    if (!c.bodies.empty()) {  // floating bodies only: a file without them is as before
        w.put<std::uint64_t>(c.bodies.size());
        w.vec(c.bodies);
    }
    if (!c.inlet_layers.empty()) {  // inlets only: a tagged block (no body block is that long)
        w.put<std::uint64_t>(kInletTag);
        w.put(c.created);
        w.put(c.inlet_next_id);
        w.put<std::uint64_t>(c.inlet_layers.size());
        w.vec(c.inlet_layers);
    }
    w.put(fnv1a(reinterpret_cast<const unsigned char*>(w.out.data()), w.out.size()));
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        f.write(w.out.data(), static_cast<std::streamsize>(w.out.size()));
        f.flush();
        if (!f) throw Error("cannot write the checkpoint " + tmp);
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) throw Error("cannot rename " + tmp + " to " + path);
}

Checkpoint read_checkpoint(const std::string& path, const Scene* scene) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw CheckpointError(path, "cannot be read");
    f.seekg(0, std::ios::end);
    const auto length = f.tellg();
    f.seekg(0, std::ios::beg);
    std::string in(length > 0 ? static_cast<std::size_t>(length) : 0, '\0');
    if (!f.read(in.data(), static_cast<std::streamsize>(in.size()))) throw CheckpointError(path, "cannot be read");
    Reader r{in, path};
    char magic[8];
    r.raw(magic, sizeof magic);
    if (std::memcmp(magic, kMagic, sizeof magic) != 0) throw CheckpointError(path, "not a clsph checkpoint (bad magic)");
    Checkpoint c;
    c.format = r.get<std::uint32_t>();
    if (c.format != kCheckpointFormat)
        throw CheckpointError(path, "format version " + std::to_string(c.format) + ", this clsph reads version " +
                                        std::to_string(kCheckpointFormat));
    if (in.size() < sizeof(std::uint64_t) + r.at) throw CheckpointError(path, "truncated");
    // The checksum first: every other field is then trusted.
    std::uint64_t stored;
    std::memcpy(&stored, in.data() + in.size() - sizeof stored, sizeof stored);
    const auto computed = fnv1a(reinterpret_cast<const unsigned char*>(in.data()), in.size() - sizeof stored);
    const std::uint32_t vlen = r.get<std::uint32_t>();
    if (vlen > 256) throw CheckpointError(path, "corrupt (checksum mismatch)");
    c.clsph_version.resize(vlen);
    r.raw(c.clsph_version.data(), vlen);
    c.scene_hash = r.get<std::uint64_t>();
    c.step = r.get<std::uint64_t>();
    c.time = r.get<double>();
    c.dt = r.get<double>();
    c.dt_next = r.get<double>();
    c.removed = r.get<std::uint64_t>();
    c.fluid = r.get<std::uint64_t>();
    c.cells = r.get<std::uint64_t>();
    c.kinetic_energy = r.get<double>();
    c.max_speed = r.get<double>();
    const auto D = r.get<std::uint64_t>();
    if (D == 0 || D > 4096) throw CheckpointError(path, stored != computed ? "corrupt (checksum mismatch)" : "corrupt (device count)");
    r.vec(c.cuts, D + 1);
    r.vec(c.counts, D);
    const auto n = r.get<std::uint64_t>();
    r.vec(c.pos, 4 * n);
    r.vec(c.velrho, 4 * n);
    r.vec(c.accel, 4 * n);
    r.vec(c.id, n);
    auto next_is_inlets = [&] {
        if (in.size() - r.at < sizeof stored + sizeof(std::uint64_t)) return false;
        std::uint64_t tag;
        std::memcpy(&tag, in.data() + r.at, sizeof tag);
        return tag == kInletTag;
    };
    if (in.size() - r.at > sizeof stored + sizeof(std::uint64_t) && !next_is_inlets()) {  // floating bodies' states
        const auto m = r.get<std::uint64_t>();
        if (m > (in.size() - r.at) / sizeof(double)) throw CheckpointError(path, stored != computed ? "corrupt (checksum mismatch)" : "truncated");
        r.vec(c.bodies, m);
    }
    if (next_is_inlets()) {  // the inlets' feed
        (void)r.get<std::uint64_t>();
        c.created = r.get<std::uint64_t>();
        c.inlet_next_id = r.get<std::uint64_t>();
        const auto m = r.get<std::uint64_t>();
        if (m == 0 || m > (in.size() - r.at) / sizeof(std::int64_t))
            throw CheckpointError(path, stored != computed ? "corrupt (checksum mismatch)" : "truncated");
        r.vec(c.inlet_layers, m);
    }
    if (in.size() - r.at != sizeof stored)
        throw CheckpointError(path, in.size() - r.at < sizeof stored ? "truncated (no checksum)" : "corrupt (trailing bytes)");
    if (stored != computed) throw CheckpointError(path, "corrupt (checksum mismatch)");
    std::uint64_t total = 0;
    for (auto k : c.counts) total += k;
    if (total != n) throw CheckpointError(path, "corrupt (device counts do not add up to the particle count)");
    if (scene && c.scene_hash != scene_hash(*scene))
        throw CheckpointError(path, "written for another scene (its scene hash differs from this run's resolved scene)");
    return c;
}

}  // namespace clsph
