// Malformed scenes: each gives a SceneError whose message names the file and the key (or the
// line and column), never a crash or a message about something else.
#include "support.hpp"

#include <clsph/scene.hpp>
#include <clsph/scene_io.hpp>

#include <vector>

using scene_test::corpus;
using scene_test::error_of;

namespace {

struct Case {
    const char* file;
    const char* expected;  // a substring of the message, after "<file>: "
};

// Every file in tests/scene/corpus/ but valid_base.json, with what its message must say.
const std::vector<Case> corpus_cases = {
    {"empty.json", "the file is empty"},
    {"render_up_zero.json", "render.camera.up: must not be the zero vector"},
    {"render_eye_at_target.json", "render.camera.eye: is at the target"},
    {"render_size_zero.json", "render.size: width and height must be positive"},
    {"render_surface_spacing_negative.json", "render.surface_spacing: must be a length in metres"},
    {"render_method_bad.json", "render.method: unknown value \"raytrace\" (expected one of \"surface\", \"splat\")"},
    {"render_up_along_view.json", "render.camera.up: must not point along the view direction"},
    {"whitespace_only.json", "the file is empty"},
    {"binary_garbage.json", "line 1, column 5: byte \\x02: this is not a text file"},
    {"top_level_array.json", "expected a JSON object at the top level, got an array"},
    {"truncated.json", "unexpected end of input"},
    {"syntax_error.json", "line 4, column 10: syntax error while parsing object separator - unexpected number literal; expected ':'"},
    {"trailing_comma.json", "line 2, column 26: syntax error while parsing object key"},
    {"duplicate_key.json", "physics.dp: duplicate key"},
    {"huge_number.json", "line 4, column 11: number overflow parsing '1e999'"},
    {"invalid_utf8.json", "line 1, column 10: syntax error while parsing value - invalid string: ill-formed UTF-8 byte"},
    {"unknown_top_key.json", "phisics: unknown key (did you mean \"physics\"?)"},
    {"unknown_physics_key.json", "physics.dpp: unknown key (did you mean \"dp\"?)"},
    {"unknown_wall_key.json", "boundaries.walls[0].layer: unknown key (did you mean \"layers\"?)"},
    {"missing_dp.json", "physics.dp: missing required key"},
    {"missing_physics.json", "physics: missing required key"},
    {"missing_domain.json", "domain: missing required key"},
    {"missing_fluid.json", "fluid: the scene has no fluid"},
    {"wrong_type_dp.json", "physics.dp: expected a number, got a string"},
    {"wrong_type_physics.json", "physics: expected an object, got a number"},
    {"wrong_type_fluid.json", "fluid: expected an array, got an object"},
    {"fluid_max_two_numbers.json", "fluid[1].max: expected 3 numbers, got 2 elements"},
    {"wrong_type_periodic.json", "domain.periodic[1]: expected true or false, got a string"},
    {"wrong_type_gravity.json", "physics.gravity: expected 3 numbers, element 2 is a string"},
    {"bad_kernel.json", "physics.kernel: unknown value \"gauss\" (expected one of \"wendland\", \"cubic\")"},
    {"bad_integrator.json", "physics.integrator: unknown value \"verlet\" (expected one of \"leapfrog\", \"symplectic\")"},
    {"bad_boundary_method.json", "boundaries.method: unknown value \"ghost\" (expected one of \"dbc\", \"mdbc\")"},
    {"bad_slip.json", "boundaries.slip: unknown value \"free\" (expected one of \"wall\", \"no-slip\")"},
    {"slip_with_dbc.json", "boundaries.slip: \"no-slip\" needs mDBC walls (boundaries.method \"mdbc\")"},
    {"alpha_wall_negative.json", "physics.alpha_wall: must be >= 0"},
    {"kinematic_viscosity_negative.json", "physics.kinematic_viscosity: must be a finite number >= 0"},
    {"bad_viscosity.json",
     "physics.viscosity: unknown value \"turbulent\" (expected one of \"artificial\", \"laminar\", \"laminar+sps\")"},
    {"bad_face.json", "boundaries.walls[0].faces[1]: unknown face \"bottom\""},
    {"layers_fraction.json", "boundaries.walls[0].layers: expected an integer, got 2.5"},
    {"layers_zero.json", "boundaries.walls[0].layers: must be 1 to 16"},
    {"bad_split_axis.json", "domain.split_axis: unknown value \"w\""},
    {"negative_c0.json", "physics.c0: must be >= 0"},
    {"gamma_not_7.json", "physics.gamma: only 7 is supported"},
    {"fluid_outside_domain.json", "fluid[0]: block [0, 0, 0] - [0.4, 0.4, 2] is not inside the domain"},
    {"dp_zero.json", "physics.dp: must be a positive number"},
    {"dp_negative.json", "physics.dp: must be a positive number"},
    {"absurd_particle_count.json", "physics.dp: gives about 64004800120001 fluid particles"},
    {"overlapping_fluid.json", "fluid[1]: overlaps fluid[0]"},
    {"domain_inverted.json", "domain.max: must be greater than domain.min"},
    {"probe_outside.json", "probes[0].point: is outside the domain"},
    {"probe_duplicate_name.json", "probes[1].name: another probe is already named \"p0\""},
    {"probe_bad_name.json", "probes[0].name: \"../p0\" is not a usable name"},
    {"height_probe_one_number.json", "probes[1].point: expected 2 or 3 numbers, got 1 element"},
    {"probe_normal_zero.json", "probes[0].normal: must not be the zero vector"},
    {"probe_size_negative.json", "probes[0].size: must be the sensor's diameter, a finite length > 0 m (got -0.009)"},
    {"probe_size_without_normal.json", "probes[0].size: a sensor's size needs its \"normal\""},
    {"height_probe_with_normal.json", "probes[0].normal: a height probe has no face"},
    {"mesh_missing.json", "boundaries.meshes[0].path: cannot read \""},
    {"mesh_negative_scale.json", "boundaries.meshes[0].scale: must be positive"},
    {"run_probe_every_zero.json", "run.probe_every: must be >= 1"},
    {"motion_overlapping_segments.json", "boundaries.boxes[0].motion.segments[1].start: overlaps the segment before it"},
    {"motion_axis_zero.json", "boundaries.boxes[0].motion.segments[0].axis: must not be the zero vector"},
    {"motion_period_zero.json", "boundaries.boxes[0].motion.segments[0].period: must be a finite time > 0 s"},
    {"motion_end_before_start.json", "boundaries.boxes[0].motion.segments[0].end: must be after start"},
    {"wave_maker_too_steep.json", "boundaries.boxes[0].motion.wave_maker.height: waves of height 0.3 m and length"},
    {"wave_maker_depth_zero.json", "boundaries.boxes[0].motion.wave_maker.depth: must be a water depth > 0 m, got 0"},
    {"motion_csv_missing.json", "/no_such_motion.csv: cannot open the motion file (No such file or directory)"},
    // Accepted silently before (issue 14): nonsense the scene check now names.
    {"coefsound_negative.json", "physics.coefsound: must be a positive number"},
    {"dp_larger_than_block.json", "fluid[0]: holds no fluid particle: no point of the dp lattice (physics.dp = 0.02 m) lies in the block"},
    {"block_between_lattice_points.json", "fluid[0]: holds no fluid particle: no point of the dp lattice"},
    {"walls_on_periodic_axis.json", "boundaries.walls[0].faces: face y- is on the periodic axis y"},
    {"walls_outside_domain.json", "boundaries.walls[0]: its particles span [-0.04, -0.04, -0.04] - [1.13, 0.44, 0.84], outside the domain"},
    {"support_below_dp.json", "physics.hdp: the kernel support 2 hdp dp = 0.016 m does not reach beyond dp = 0.02 m"},
    {"fluid_inside_solid.json", "fluid[0]: overlaps the solid boundaries.boxes[0]"},
    {"fixed_dt_negative.json", "run.fixed_dt: must be a finite time >= 0 s"},
    {"mesh_is_directory.json", "boundaries.meshes[0].path: cannot read \"" },
    {"mesh_dev_zero.json", "boundaries.meshes[0].path: cannot read \"/dev/zero\": it is not a regular file"},
    {"mesh_unknown_format.json", "boundaries.meshes[0].path: cannot read \""},
    {"end_time_infinite_text.json", "run.end_time: expected a number, got a string"},
};

// Scenes whose mistake shows only when the particles are made (a block emptied by the walls
// beside it, a mesh file's contents): Scene::build_particles names the key (and the file, line).
const std::vector<Case> build_cases = {
    {"fluid_within_dp_of_walls.json", "fluid[0]: no fluid particle is left in the block [0, 0, 0] - [0.01, 0.4, 0.4]: each of its 441 lattice points is within dp of a boundary particle"},
    {"mesh_nan_vertex.json", "boundaries.meshes[0].path: "},
    {"mesh_huge_vertex.json", "boundaries.meshes[0].path: "},
    {"mesh_nan_vertex_stl.json", "boundaries.meshes[0].path: "},
    {"mesh_open_ply.json", "boundaries.meshes[0].path: "},
};

}  // namespace

TEST_CASE("every malformed scene in the corpus names its file and key") {
    for (const auto& c : corpus_cases) {
        CAPTURE(c.file);
        const std::string path = corpus(c.file);
        const std::string message = error_of([&] { (void)clsph::Scene::from_file(path); });
        CAPTURE(message);
        CHECK(message.rfind(path + ": ", 0) == 0);  // begins with the file
        CHECK(message.find(c.expected) != std::string::npos);
    }
}

TEST_CASE("scenes whose mistake shows when the particles are made name the key") {
    for (const auto& c : build_cases) {
        CAPTURE(c.file);
        const clsph::Scene scene = clsph::Scene::from_file(corpus(c.file));  // the values are fine
        const std::string message = error_of([&] { (void)scene.build_particles(); });
        CAPTURE(message);
        CHECK(message.rfind(c.expected, 0) == 0);
    }
    const std::string nan = error_of([] { (void)clsph::Scene::from_file(corpus("mesh_nan_vertex.json")).build_particles(); });
    CHECK(nan.find("nan_vertex.obj: line 8: vertex coordinate 'nan' is not a finite number") != std::string::npos);
    const std::string huge = error_of([] { (void)clsph::Scene::from_file(corpus("mesh_huge_vertex.json")).build_particles(); });
    CHECK(huge.find("huge_vertex.obj: line 8: vertex coordinate '1e300' is not a finite number of at most 1e9") != std::string::npos);
    const std::string stl = error_of([] { (void)clsph::Scene::from_file(corpus("mesh_nan_vertex_stl.json")).build_particles(); });
    CHECK(stl.find("nan_vertex.stl: triangle 3 (line 20): vertex 3 is not finite (y = nan)") != std::string::npos);
    const std::string open = error_of([] { (void)clsph::Scene::from_file(corpus("mesh_open_ply.json")).build_particles(); });
    CHECK(open.find("open.ply: the mesh is not closed: 4 of 17 edges are not shared by exactly two triangles") != std::string::npos);
    const std::string off = error_of([] { (void)clsph::Scene::from_file(corpus("mesh_unknown_format.json")); });
    CHECK(off.find("cube.off\": not a mesh format clsph reads (the name must end in .obj, .stl or .ply)") != std::string::npos);
}

TEST_CASE("only regular files are read as scenes: a directory or a device is named as such") {
    const std::string dir = corpus("");
    CHECK(error_of([&] { (void)clsph::Scene::from_file(dir); }) == dir + ": cannot read: it is a directory, not a file");
    CHECK(error_of([] { (void)clsph::Scene::from_file("/dev/zero"); }) ==
          "/dev/zero: cannot read: it is not a regular file (a device, a pipe or a socket)");
    CHECK(error_of([] { (void)clsph::Scene::from_file("/dev/urandom"); }) ==
          "/dev/urandom: cannot read: it is not a regular file (a device, a pipe or a socket)");
}

TEST_CASE("the corpus table covers every corpus file") {
    std::size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(corpus(""))) {
        const std::string name = entry.path().filename().string();
        if (name == "valid_base.json") continue;
        ++files;
        bool listed = false;
        for (const auto& c : corpus_cases) listed = listed || name == c.file;
        for (const auto& c : build_cases) listed = listed || name == c.file;
        CHECK_MESSAGE(listed, name << " has no expected message in corpus_cases");
    }
    CHECK(files == corpus_cases.size() + build_cases.size());
}

TEST_CASE("a missing scene file names the file and the OS error") {
    const std::string path = corpus("no_such_scene.json");
    CHECK(error_of([&] { (void)clsph::Scene::from_file(path); }) == path + ": cannot read: No such file or directory");
}

TEST_CASE("a missing mesh names the resolved path, relative to the scene's directory") {
    const std::string message = error_of([&] { (void)clsph::Scene::from_file(corpus("mesh_missing.json")); });
    CHECK(message.find(std::filesystem::path(corpus("no_such_mesh.obj")).lexically_normal().string()) != std::string::npos);
}

TEST_CASE("from_json_text names the source it is given") {
    CHECK(error_of([] { (void)clsph::Scene::from_json_text("{\"physics\": {}}", "inline.json"); }) ==
          "inline.json: physics.dp: missing required key");
    CHECK(error_of([] { (void)clsph::Scene::from_json_text("{\n  \"physics\": {\"dp\": 0.01}\n}", "inline.json"); }) ==
          "inline.json: domain: missing required key");
}

TEST_CASE("bad --set overrides name the file, the override and the key") {
    const std::string base = corpus("valid_base.json");
    struct Override {
        const char* set;
        const char* expected;
    };
    const std::vector<Override> cases = {
        {"physics.dpp=1", "physics.dpp: unknown key (did you mean \"dp\"?) (set by --set physics.dpp=1)"},
        {"physics.dp=0", "physics.dp: must be a positive number (got 0.000000) (set by --set physics.dp=0)"},
        {"physics.kernel=gauss", "physics.kernel: unknown value \"gauss\" (expected one of \"wendland\", \"cubic\") (set by --set physics.kernel=gauss)"},
        {"fluid[0].max=[1,2]", "fluid[0].max: expected 3 numbers, got 2 elements (set by --set fluid[0].max=[1,2])"},
        {"fluid.0.max=oops", "fluid[0].max: expected 3 numbers, got a string (set by --set fluid.0.max=oops)"},
        {"fluid[1]={\"min\":[0.1,0,0],\"max\":[0.3,0.2,0.2]}", "fluid[1]: overlaps fluid[0] (set by --set fluid[1]="},
        {"physics.dp", "--set physics.dp: expected KEY=VALUE"},
        {"=3", "--set =3: empty key"},
        {"physics..dp=1", "--set physics..dp=1: empty key between dots"},
        {"physics.dp.=1", "--set physics.dp.=1: the key ends with '.'"},
        {"fluid[x].max=1", "--set fluid[x].max=1: '[x]' is not an array index"},
        {"fluid[0.max=1", "--set fluid[0.max=1: unclosed '[' in the key"},
        {"fluid[5].max=[1,1,1]", "--set fluid[5].max=[1,1,1]: fluid[5]: index out of range (the array has 1 elements)"},
        {"physics.dp.x=1", "--set physics.dp.x=1: physics.dp is a number, which has no key \"x\""},
        {"physics[0]=1", "--set physics[0]=1: physics is an object, which has no element [0]"},
    };
    for (const auto& c : cases) {
        CAPTURE(c.set);
        const std::string message = error_of([&] { (void)clsph::load_scene(base, {c.set}); });
        CAPTURE(message);
        CHECK(message.rfind(base + ": ", 0) == 0);
        CHECK(message.find(c.expected) != std::string::npos);
    }
}
