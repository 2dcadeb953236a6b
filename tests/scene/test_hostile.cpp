// Hostile scenes through the C++ API: Scene::validate() checks exactly what the JSON reader checks,
// with the same messages (the reader checks syntax and types, then calls validate()), including
// what JSON cannot even spell (NaN); and hostile sizes answer within seconds.
#include "support.hpp"

#include <clsph/scene.hpp>

#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

using scene_test::error_of;

namespace {

clsph::Scene valid_scene() {
    clsph::Scene s;
    s.physics.dp = 0.02;
    s.domain.min = {-0.1, -0.1, -0.1};
    s.domain.max = {1.1, 0.5, 1.0};
    clsph::FluidBlock f;
    f.max = {0.4, 0.4, 0.4};
    s.fluids.push_back(f);
    clsph::BoxWalls w;
    w.max = {1.0, 0.4, 0.8};
    s.walls.push_back(w);
    clsph::Probe p;
    p.name = "p0";
    p.point = {0.2, 0.2, 0.1};
    s.probes.push_back(p);
    return s;
}

struct Mistake {
    const char* what;
    std::function<void(clsph::Scene&)> make;
    const char* expected;  // the message begins with this
};

const double nan = std::numeric_limits<double>::quiet_NaN();

// A boundary mesh read from `path`, the other keys at their defaults.
clsph::MeshObject mesh_file(const std::string& path, double scale) {
    clsph::MeshObject m;
    m.path = path;
    m.scale = scale;
    return m;
}

// Mistakes JSON can carry: both paths must give the same message.
const std::vector<Mistake> both_paths = {
    {"negative coefsound", [](clsph::Scene& s) { s.physics.coefsound = -1; }, "physics.coefsound: must be a positive number"},
    {"negative c0", [](clsph::Scene& s) { s.physics.c0 = -1; }, "physics.c0: must be >= 0"},
    {"a probe name with ../", [](clsph::Scene& s) { s.probes[0].name = "../p0"; }, "probes[0].name: \"../p0\" is not a usable name"},
    {"two probes of one name", [](clsph::Scene& s) { s.probes.push_back(s.probes[0]); }, "probes[1].name: another probe is already named \"p0\""},
    {"a negative fixed dt", [](clsph::Scene& s) { s.run.fixed_dt = -1e-4; }, "run.fixed_dt: must be a finite time >= 0 s"},
    {"walls with no faces", [](clsph::Scene& s) { s.walls[0].faces = 0; }, "boundaries.walls[0].faces: expected at least one face"},
    {"walls with 0 layers", [](clsph::Scene& s) { s.walls[0].layers = 0; }, "boundaries.walls[0].layers: must be 1 to 16 (got 0)"},
    {"a solid with 17 layers", [](clsph::Scene& s) { s.solids.push_back({{0.6, 0, 0}, {0.8, 0.2, 0.2}, 17, {}}); }, "boundaries.boxes[0].layers: must be 0 to 16 (got 17)"},
    {"walls on a periodic axis", [](clsph::Scene& s) { s.domain.periodic[1] = true; }, "boundaries.walls[0].faces: face y- is on the periodic axis y"},
    {"walls outside the domain", [](clsph::Scene& s) { s.walls[0].max[0] = 1.09; }, "boundaries.walls[0]: its particles span"},
    {"a support below dp", [](clsph::Scene& s) { s.physics.hdp = 0.4; }, "physics.hdp: the kernel support"},
    {"fluid inside a solid", [](clsph::Scene& s) { s.solids.push_back({{0.1, 0.1, 0.1}, {0.3, 0.3, 0.3}, 3, {}}); }, "fluid[0]: overlaps the solid boundaries.boxes[0]"},
    {"a block between lattice points", [](clsph::Scene& s) { s.fluids[0].min[0] = 0.105, s.fluids[0].max[0] = 0.115; }, "fluid[0]: holds no fluid particle"},
    {"a block smaller than dp", [](clsph::Scene& s) { s.fluids[0].min = {0.101, 0.101, 0.101}, s.fluids[0].max = {0.119, 0.119, 0.119}; }, "fluid[0]: holds no fluid particle"},
    {"overlapping blocks", [](clsph::Scene& s) { s.fluids.push_back({{0.3, 0, 0}, {0.5, 0.2, 0.2}, {0, 0, 0}, {}}); }, "fluid[1]: overlaps fluid[0]"},
    {"a zero frame interval", [](clsph::Scene& s) { s.run.output_every = 0; }, "run.output_every: must be a finite time > 0 s"},
    {"a probe outside", [](clsph::Scene& s) { s.probes[0].point = {5, 0, 0}; }, "probes[0].point: is outside the domain"},
    {"a sensor facing nowhere", [](clsph::Scene& s) { s.probes[0].normal = clsph::Vec3{0, 0, 0}; }, "probes[0].normal: must not be the zero vector"},
    {"a sensor of no size", [](clsph::Scene& s) { s.probes[0].normal = clsph::Vec3{1, 0, 0}, s.probes[0].size = 0; }, "probes[0].size: must be the sensor's diameter"},
    {"a missing mesh", [](clsph::Scene& s) { s.meshes.push_back(mesh_file("/no/such/mesh.obj", 1.0)); }, "boundaries.meshes[0].path: cannot read \"/no/such/mesh.obj\": No such file or directory"},
    {"a mesh that is a device", [](clsph::Scene& s) { s.meshes.push_back(mesh_file("/dev/zero", 1.0)); }, "boundaries.meshes[0].path: cannot read \"/dev/zero\": it is not a regular file"},
};

// NaN has no JSON spelling (it is written as null): only the C++ path can carry it, and it must be
// refused there, naming the key.
const std::vector<Mistake> cpp_only = {
    {"NaN c0", [](clsph::Scene& s) { s.physics.c0 = nan; }, "physics.c0: must be >= 0"},
    {"NaN gravity", [](clsph::Scene& s) { s.physics.gravity[2] = nan; }, "physics.gravity: expected 3 finite numbers"},
    {"NaN velocity", [](clsph::Scene& s) { s.fluids[0].velocity[0] = nan; }, "fluid[0].velocity: expected 3 finite numbers"},
    {"NaN surface", [](clsph::Scene& s) { s.fluids[0].surface = nan; }, "fluid[0].surface: must be a finite height"},
    {"NaN block corner", [](clsph::Scene& s) { s.fluids[0].max[1] = nan; }, "fluid[0].max: expected 3 finite numbers"},
    {"NaN probe point", [](clsph::Scene& s) { s.probes[0].point[0] = nan; }, "probes[0].point: expected 3 finite numbers"},
    {"NaN sensor normal", [](clsph::Scene& s) { s.probes[0].normal = clsph::Vec3{nan, 1, 0}; }, "probes[0].normal: expected 3 finite numbers"},
    {"NaN sensor size", [](clsph::Scene& s) { s.probes[0].normal = clsph::Vec3{1, 0, 0}, s.probes[0].size = nan; }, "probes[0].size: must be the sensor's diameter"},
    // The resolved scene writes no face for a height probe, so only code can give one.
    {"a height probe with a face", [](clsph::Scene& s) { s.probes[0].kind = clsph::Probe::Kind::height, s.probes[0].normal = clsph::Vec3{0, 0, 1}; }, "probes[0].normal: a height probe has no face"},
    {"NaN domain", [](clsph::Scene& s) { s.domain.max[0] = nan; }, "domain.max: expected 3 finite numbers"},
    {"infinite end time", [](clsph::Scene& s) { s.run.end_time = std::numeric_limits<double>::infinity(); }, "run.end_time: must be a finite time >= 0 s"},
    {"NaN fixed dt", [](clsph::Scene& s) { s.run.fixed_dt = nan; }, "run.fixed_dt: must be a finite time >= 0 s"},
    // JSON spells only the two names (an unknown one: tests/scene/corpus/render_method_bad.json).
    {"a render method out of range", [](clsph::Scene& s) { s.render.method = static_cast<clsph::RenderMethod>(7); }, "render.method: must be \"surface\" or \"splat\""},
    {"a mesh path that is /dev/null", [](clsph::Scene& s) { s.meshes.push_back(mesh_file("/dev/null", nan)); }, "boundaries.meshes[0].path: cannot read \"/dev/null\": it is not a regular file"},
};

}  // namespace

TEST_CASE("the valid scene of these tests is valid on both paths") {
    const clsph::Scene s = valid_scene();
    CHECK_NOTHROW(s.validate());
    CHECK_NOTHROW((void)clsph::Scene::from_json_text(s.to_json(), "scene.json"));
}

TEST_CASE("Scene::validate and the JSON reader refuse the same mistakes with the same message") {
    for (const auto& m : both_paths) {
        CAPTURE(m.what);
        clsph::Scene s = valid_scene();
        m.make(s);
        const std::string from_code = error_of([&] { s.validate(); });
        const std::string from_json = error_of([&] { (void)clsph::Scene::from_json_text(s.to_json(), "scene.json"); });
        CAPTURE(from_code);
        CAPTURE(from_json);
        CHECK(from_code.rfind(m.expected, 0) == 0);
        CHECK(from_json == "scene.json: " + from_code);
    }
}

TEST_CASE("values JSON cannot spell are refused by Scene::validate, naming the key") {
    for (const auto& m : cpp_only) {
        CAPTURE(m.what);
        clsph::Scene s = valid_scene();
        m.make(s);
        const std::string message = error_of([&] { s.validate(); });
        CAPTURE(message);
        CHECK(message.rfind(m.expected, 0) == 0);
    }
}

TEST_CASE("run.fixed_dt is read from JSON and written back") {
    clsph::Scene s = valid_scene();
    s.run.fixed_dt = 2.5e-5;
    const clsph::Scene back = clsph::Scene::from_json_text(s.to_json(), "scene.json");
    CHECK(back.run.fixed_dt == 2.5e-5);
    CHECK(s.to_json().find("\"fixed_dt\": 2.5e-05") != std::string::npos);
}

TEST_CASE("a scene with no fluid particle left is an error, not an empty run") {
    clsph::Scene s = valid_scene();
    s.fluids[0].max = {0.01, 0.4, 0.4};  // the lattice plane x = 0, on the x- wall
    CHECK(error_of([&] { (void)s.build_particles(); }).rfind("fluid[0]: no fluid particle is left in the block", 0) == 0);
    // Fluid in the middle of the tank beside it is still fine.
    s.fluids.push_back({{0.5, 0.1, 0.1}, {0.7, 0.3, 0.3}, {0, 0, 0}, {}});
    CHECK(error_of([&] { (void)s.build_particles(); }).rfind("fluid[0]: ", 0) == 0);
    s.fluids.erase(s.fluids.begin());
    CHECK(s.build_particles().size() > 0);
}

// Set-up is near-linear in the number of blocks: 100,000 one-particle blocks on a grid (each pair
// compared, as before, took minutes). The bound is a hang guard, 20x what a 2-core machine needs.
TEST_CASE("100,000 fluid blocks are checked and built within seconds") {
    clsph::Scene s = valid_scene();
    s.physics.dp = 0.01;
    s.domain.max = {2.1, 1.1, 1.0};
    s.walls[0].max = {2.0, 1.0, 0.9};
    s.walls[0].faces = clsph::z_min;
    s.probes.clear();
    s.fluids.clear();
    for (int i = 0; i < 100; ++i)
        for (int j = 0; j < 50; ++j)
            for (int k = 0; k < 20; ++k) {
                const double x = 0.02 * i + 0.005, y = 0.02 * j + 0.005, z = 0.02 * k + 0.045;
                s.fluids.push_back({{x, y, z}, {x + 0.011, y + 0.011, z + 0.011}, {0, 0, 0}, {}});
            }
    const auto start = std::chrono::steady_clock::now();
    const clsph::Particles p = s.build_particles();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    MESSAGE("100,000 blocks: " << p.size() << " particles in " << seconds << " s");
    CHECK(p.size() > 100000);
    CHECK(seconds < 20.0);
    // And an overlap among them is still found, naming the later block and the earlier one.
    s.fluids.push_back({{0.0, 0.0, 0.04}, {0.03, 0.03, 0.07}, {0, 0, 0}, {}});
    CHECK(error_of([&] { s.validate(); }) == "fluid[100000]: overlaps fluid[0]");
}
