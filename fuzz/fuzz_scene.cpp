// The scene loader as `clsph run SCENE --set ...` drives it: the input is a scene file, optionally
// preceded by lines "#set KEY=VALUE" (each one --set override, in order). Every input must end in
// a Scene or a clsph::SceneError, never a crash, a sanitizer report, a hang or a huge allocation;
// a scene that loads and is small is also built into particles.
#include "clsph/error.hpp"
#include "clsph/scene.hpp"
#include "scene/json_scene.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace {

// Lattice points of the fluid blocks, walls and boxes: only small scenes are built.
double rough_particles(const clsph::Scene& s) {
    const double dp = s.physics.dp;
    double n = 0;
    auto box = [&](const clsph::Vec3& a, const clsph::Vec3& b, double grow) {
        double m = 1;
        for (int k = 0; k < 3; ++k) m *= (b[k] - a[k] + 2 * grow) / dp + 1;
        return m;
    };
    for (const auto& f : s.fluids) n += box(f.min, f.max, 0);
    for (const auto& w : s.walls) n += box(w.min, w.max, w.layers * dp);
    for (const auto& b : s.solids) n += box(b.min, b.max, 0);
    return n;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string text(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> overrides;
    while (text.rfind("#set ", 0) == 0) {
        const auto end = text.find('\n');
        overrides.push_back(text.substr(5, end == std::string::npos ? std::string::npos : end - 5));
        text = end == std::string::npos ? std::string() : text.substr(end + 1);
    }
    try {
        const clsph::Scene s = clsph::scene::load_scene_text(text, "fuzz.json", overrides);
        (void)s.to_json();
        if (s.meshes.empty() && rough_particles(s) < 2e4) (void)s.build_particles();
    } catch (const clsph::SceneError&) {
    }
    return 0;
}
