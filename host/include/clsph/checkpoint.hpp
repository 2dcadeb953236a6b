// Checkpoints (docs/checkpoint.md): the state a run needs to go on bitwise as if it had never
// stopped — every per-particle array the next step reads, as held on the devices and in their
// order, the step counters, the cuts — in a versioned binary file with a checksum.
#pragma once
#include "clsph/error.hpp"
#include "clsph/scene.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace clsph {

// A checkpoint that cannot be used: corrupt, truncated, another scene's, another format version.
// what() names the file and the reason.
class CheckpointError : public Error {
public:
    CheckpointError(const std::string& path, const std::string& reason)
        : Error("checkpoint " + path + ": " + reason), path_(path), reason_(reason) {}
    const std::string& path() const { return path_; }
    const std::string& reason() const { return reason_; }

private:
    std::string path_, reason_;
};

constexpr std::uint32_t kCheckpointFormat = 2;  // 2: the type in the top bit of the id word (1: two bits)

struct Checkpoint {
    std::uint32_t format = kCheckpointFormat;
    std::string clsph_version;
    std::uint64_t scene_hash = 0;
    // The step counters after the last step taken (StepInfo), and the step the next one takes.
    std::uint64_t step = 0;
    double time = 0, dt = 0, dt_next = 0;
    std::uint64_t removed = 0, fluid = 0, cells = 0;
    std::uint64_t created = 0;  // by the inlets (with inlets only; see `inlets`)
    double kinetic_energy = 0, max_speed = 0;
    // The cuts (devices + 1 columns) and each device's owned particles, in slab order.
    std::vector<std::uint64_t> cuts, counts;
    // The particle arrays as held on the devices, slab after slab, each in its device's order:
    // pos (offset from the cell centre xyz + key bits w), velrho, accel (xyz + drho/dt), id words.
    std::vector<float> pos, velrho, accel;
    std::vector<std::uint32_t> id;
    // Floating bodies (docs/scenes.md, floating): each body's state in double, body after body
    // (empty without them; the file then has no such block).
    std::vector<double> bodies;
    // Inlets (docs/scenes.md, inlets): the next id and each inlet's last layer made (empty without
    // inlets; the file then has no such block).
    std::uint64_t inlet_next_id = 0;
    std::vector<std::int64_t> inlet_layers;
    std::size_t size() const { return id.size(); }
};

// A hash of the resolved scene (Scene::to_json) with the run's end time left out (--until may
// move it): a checkpoint is only read back into the scene it was written from.
std::uint64_t scene_hash(const Scene& scene);

// Writes `c` to `path` through `path`.tmp and a rename (a crash leaves the old file or the new).
void write_checkpoint(const std::string& path, const Checkpoint& c);
// Reads and checks (magic, format version, length, checksum; with `scene`, its hash) a
// checkpoint; throws CheckpointError naming the file and the reason.
Checkpoint read_checkpoint(const std::string& path, const Scene* scene = nullptr);

}  // namespace clsph
