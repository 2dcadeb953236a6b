// Scene files: defaults, every key read into the Scene, to_json round trips, --set overrides.
#include "support.hpp"

#include <clsph/scene.hpp>
#include <clsph/scene_io.hpp>

using scene_test::corpus;
using scene_test::error_of;

namespace {

const char* full_scene = R"({
  "name": "everything",
  "physics": {"dp": 0.02, "hdp": 1.5, "kernel": "cubic", "density": "summation", "diffusion": "molteni",
              "delta": 0.05, "rho0": 998.2, "gamma": 7, "coefsound": 15, "c0": 30, "alpha": 0.05,
              "viscosity": "laminar", "kinematic_viscosity": 2.5e-5,
              "gravity": [0, -1, -9.8], "cfl": 0.25, "density_min": 0.8, "density_max": 1.2},
  "domain": {"min": [-0.1, -0.1, -0.1], "max": [2.1, 0.5, 1.1], "periodic": [false, true, false], "split_axis": "x"},
  "fluid": [{"min": [0, 0, 0], "max": [0.5, 0.4, 0.5], "velocity": [1, 0, 0], "surface": 0.6},
            {"min": [1, 0, 0], "max": [1.5, 0.4, 0.2]}],
  "boundaries": {
    "walls": [{"min": [0, 0, 0], "max": [2, 0.4, 1], "faces": ["x-", "x+", "z-"], "layers": 2}],
    "boxes": [{"min": [0.7, 0, 0], "max": [0.8, 0.4, 0.1], "layers": 0}],
    "meshes": []
  },
  "probes": [{"name": "P1", "kind": "pressure", "point": [0.1, 0.2, 0.05]},
             {"name": "H1", "kind": "height", "point": [1.2, 0.2]},
             {"name": "S1", "kind": "pressure", "point": [0, 0.2, 0.1], "normal": [2, 0, 0], "size": 0.02}],
  "run": {"end_time": 0.75, "output_every": 0.05, "probe_every": 3},
  "render": {"method": "splat", "size": [640, 360]}
})";

}  // namespace

TEST_CASE("every key of a scene file reaches the Scene") {
    const clsph::Scene s = clsph::Scene::from_json_text(full_scene, "everything.json");
    CHECK(s.name == "everything");
    const auto& p = s.physics;
    CHECK(p.dp == 0.02);
    CHECK(p.hdp == 1.5);
    CHECK(p.kernel == clsph::KernelType::cubic_spline);
    CHECK(p.density == clsph::DensityMode::summation);
    CHECK(p.diffusion == clsph::Diffusion::molteni_colagrossi);
    CHECK(p.delta == 0.05);
    CHECK(p.rho0 == 998.2);
    CHECK(p.coefsound == 15);
    CHECK(p.c0 == 30);
    CHECK(p.alpha == 0.05);
    CHECK(p.viscosity == clsph::Viscosity::laminar);
    CHECK(p.kinematic_viscosity == 2.5e-5);
    CHECK(p.gravity == clsph::Vec3{0, -1, -9.8});
    CHECK(p.cfl == 0.25);
    CHECK(p.density_min == 0.8);
    CHECK(p.density_max == 1.2);
    CHECK(s.domain.periodic == std::array<bool, 3>{false, true, false});
    CHECK(s.domain.split_axis == 0);
    REQUIRE(s.fluids.size() == 2);
    CHECK(s.fluids[0].velocity == clsph::Vec3{1, 0, 0});
    CHECK(s.fluids[0].surface == 0.6);
    CHECK(!s.fluids[1].surface.has_value());
    REQUIRE(s.walls.size() == 1);
    CHECK(s.walls[0].faces == (clsph::x_min | clsph::x_max | clsph::z_min));
    CHECK(s.walls[0].layers == 2);
    REQUIRE(s.solids.size() == 1);
    CHECK(s.solids[0].layers == 0);
    REQUIRE(s.probes.size() == 3);
    CHECK(s.probes[1].kind == clsph::Probe::Kind::height);
    CHECK(s.probes[1].point == clsph::Vec3{1.2, 0.2, 0});
    CHECK(!s.probes[0].normal.has_value());  // a point probe
    CHECK(s.probes[0].size == clsph::Probe{}.size);
    CHECK(s.probes[2].normal == clsph::Vec3{2, 0, 0});  // as given: normalised where it is used
    CHECK(s.probes[2].size == 0.02);
    CHECK(s.run.end_time == 0.75);
    CHECK(s.run.output_every == 0.05);
    CHECK(s.run.probe_every == 3);
    CHECK(s.render.method == clsph::RenderMethod::splat);
    CHECK(s.render.width == 640);
}

TEST_CASE("omitted keys take the documented defaults") {
    const clsph::Scene s = clsph::Scene::from_json_text(
        R"({"physics": {"dp": 0.05}, "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
            "fluid": [{"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}]})",
        "defaults.json");
    const clsph::PhysicsParams d;
    CHECK(s.name == "defaults");  // the file name's stem
    CHECK(s.physics.hdp == d.hdp);
    CHECK(s.physics.kernel == clsph::KernelType::wendland_c2);
    CHECK(s.physics.diffusion == clsph::Diffusion::fourtakas);
    CHECK(s.physics.viscosity == clsph::Viscosity::artificial);
    CHECK(s.physics.kinematic_viscosity == d.kinematic_viscosity);
    CHECK(s.physics.gravity == d.gravity);
    CHECK(s.domain.split_axis == -1);
    CHECK(s.walls.empty());
    CHECK(s.run.end_time == clsph::RunControl{}.end_time);
    CHECK(s.render.method == clsph::RenderMethod::surface);
}

TEST_CASE("walls by default: mDBC with wall friction; DBC, and a note, for a scene with floating bodies") {
    auto scene = [](const std::string& physics, const std::string& boundaries) {
        return clsph::Scene::from_json_text(R"({"physics": {"dp": 0.05)" + physics + R"(},
            "domain": {"min": [-0.2, -0.2, -0.2], "max": [1.2, 0.6, 1.2]},
            "fluid": [{"min": [0, 0, 0], "max": [1, 0.4, 0.25]}],
            "boundaries": {"walls": [{"min": [0, 0, 0], "max": [1, 0.4, 1]}])" + boundaries + "}}",
                                            "walls.json");
    };
    const clsph::Scene plain = scene("", "");
    CHECK(plain.boundary_method == clsph::BoundaryMethod::mdbc);
    CHECK(plain.physics.alpha_wall == clsph::kMdbcWallFriction);
    CHECK(plain.notes.empty());
    const clsph::Scene given = scene(R"(, "alpha_wall": 0.1)", "");
    CHECK(given.physics.alpha_wall == 0.1);  // a given friction is kept
    const clsph::Scene none = scene(R"(, "alpha_wall": 0)", "");
    CHECK(none.physics.alpha_wall == 0.0);
    const clsph::Scene dbc = scene("", R"(, "method": "dbc")");
    CHECK(dbc.boundary_method == clsph::BoundaryMethod::dbc);
    CHECK(dbc.physics.alpha_wall == 0.0);  // DBC's gap is its friction
    const clsph::Scene mdbc = scene("", R"(, "method": "mdbc")");
    CHECK(mdbc.physics.alpha_wall == clsph::kMdbcWallFriction);
    // Round trips keep the walls (to_json writes the method and the friction).
    const clsph::Scene back = clsph::Scene::from_json_text(plain.to_json(), "back.json");
    CHECK(back.to_json() == plain.to_json());
    CHECK(clsph::Scene::from_json_text(dbc.to_json(), "back.json").boundary_method == clsph::BoundaryMethod::dbc);
    // Floating bodies: mDBC as every scene, no note; dbc selectable.
    const std::string box = R"(, "boxes": [{"min": [0.5, 0.1, 0.2], "max": [0.7, 0.3, 0.3], "layers": 0, "floating": {"density": 500}}])";
    const clsph::Scene floating = scene("", box);
    CHECK(floating.boundary_method == clsph::BoundaryMethod::mdbc);
    CHECK(floating.physics.alpha_wall == clsph::kMdbcWallFriction);
    CHECK(floating.notes.empty());
    CHECK(scene("", box + R"(, "method": "dbc")").boundary_method == clsph::BoundaryMethod::dbc);
    CHECK(clsph::Scene::from_json_text(floating.to_json(), "back.json").notes.empty());
}

TEST_CASE("boundaries.slip: the walls' own velocity by default, no-slip with mDBC walls, kept by to_json") {
    auto scene = [](const std::string& boundaries) {
        return clsph::Scene::from_json_text(R"({"physics": {"dp": 0.05},
            "domain": {"min": [-0.2, -0.2, -0.2], "max": [1.2, 0.6, 1.2]},
            "fluid": [{"min": [0, 0, 0], "max": [1, 0.4, 0.25]}],
            "boundaries": {"walls": [{"min": [0, 0, 0], "max": [1, 0.4, 1]}])" + boundaries + "}}",
                                            "slip.json");
    };
    CHECK(scene("").wall_slip == clsph::WallSlip::wall);
    CHECK(scene(R"(, "method": "dbc")").wall_slip == clsph::WallSlip::wall);
    CHECK(scene(R"(, "slip": "wall")").wall_slip == clsph::WallSlip::wall);
    const clsph::Scene no_slip = scene(R"(, "slip": "no-slip")");  // the default walls are mDBC
    CHECK(no_slip.wall_slip == clsph::WallSlip::no_slip);
    CHECK(no_slip.boundary_method == clsph::BoundaryMethod::mdbc);
    const clsph::Scene back = clsph::Scene::from_json_text(no_slip.to_json(), "back.json");
    CHECK(back.wall_slip == clsph::WallSlip::no_slip);
    CHECK(back.to_json() == no_slip.to_json());
    CHECK(scene("").to_json().find(R"("slip": "wall")") != std::string::npos);  // the resolved scene says which
    // A scene built in C++ is checked alike.
    clsph::Scene dbc = scene(R"(, "method": "dbc")");
    dbc.wall_slip = clsph::WallSlip::no_slip;
    CHECK(scene_test::error_of([&] { dbc.validate(); }).find("boundaries.slip: \"no-slip\" needs mDBC walls") !=
          std::string::npos);
}

TEST_CASE("to_json writes every default and reads back to the same scene") {
    const clsph::Scene s = clsph::Scene::from_json_text(full_scene, "everything.json");
    const std::string text = s.to_json();
    const clsph::Scene back = clsph::Scene::from_json_text(text, "resolved.json");
    CHECK(back.to_json() == text);
    CHECK(back.physics.hdp == s.physics.hdp);
    CHECK(back.physics.viscosity == clsph::Viscosity::laminar);
    CHECK(back.physics.kinematic_viscosity == s.physics.kinematic_viscosity);
    CHECK(back.fluids[0].surface == s.fluids[0].surface);
    CHECK(back.walls[0].faces == s.walls[0].faces);
    CHECK(back.probes[0].normal == s.probes[0].normal);
    CHECK(back.probes[2].normal == s.probes[2].normal);
    CHECK(back.probes[2].size == s.probes[2].size);
    CHECK(back.render.method == clsph::RenderMethod::splat);
    CHECK(text.find(R"("normal": [)") != std::string::npos);
    CHECK(text.find(R"("size": 0.02)") != std::string::npos);

    // A minimal scene: the defaults become explicit keys.
    const clsph::Scene minimal = clsph::Scene::from_file(corpus("valid_base.json"));
    const std::string resolved = minimal.to_json();
    for (const char* key : {"\"hdp\"", "\"kernel\": \"wendland\"", "\"diffusion\": \"fourtakas\"", "\"periodic\"",
                            "\"split_axis\": \"auto\"", "\"velocity\"", "\"surface\": null", "\"output_every\"",
                            "\"normal\": null", "\"method\": \"surface\""})
        CHECK_MESSAGE(resolved.find(key) != std::string::npos, key);
    CHECK(clsph::Scene::from_json_text(resolved, "resolved.json").to_json() == resolved);
}

TEST_CASE("--set overrides change the document before it is read") {
    const std::string base = corpus("valid_base.json");
    const clsph::Scene s = clsph::load_scene(
        base, {"physics.dp=0.025", "physics.kernel=cubic", "fluid.0.max=[0.3,0.3,0.3]", "fluid[0].velocity=[1,0,0]",
               "probes[1]={\"name\":\"h\",\"kind\":\"height\",\"point\":[0.5,0.2]}", "run.probe_every=4",
               "name=\"renamed\"", "domain.periodic=[false,false,false]"});
    CHECK(s.physics.dp == 0.025);
    CHECK(s.physics.kernel == clsph::KernelType::cubic_spline);
    CHECK(s.fluids[0].max == clsph::Vec3{0.3, 0.3, 0.3});
    CHECK(s.fluids[0].velocity == clsph::Vec3{1, 0, 0});
    REQUIRE(s.probes.size() == 2);
    CHECK(s.probes[1].name == "h");
    CHECK(s.run.probe_every == 4);
    CHECK(s.name == "renamed");
    // The later override wins; a key absent from the file is created.
    CHECK(clsph::load_scene(base, {"physics.dp=0.03", "physics.dp=0.04"}).physics.dp == 0.04);
    CHECK(clsph::load_scene(base, {"physics.c0=40"}).physics.c0 == 40);
}

TEST_CASE("mesh paths are resolved against the scene file's directory") {
    scene_test::TempDir dir;
    std::filesystem::create_directories(dir.path() / "meshes");
    std::filesystem::create_directories(dir.path() / "scenes");
    scene_test::write_text(dir.file("meshes/box.obj"),
                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                           "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
    scene_test::write_text(dir.file("scenes/drop.json"),
                           R"({"physics": {"dp": 0.1, "c0": 20}, "domain": {"min": [-1, -1, -1], "max": [2, 2, 2]},
                               "boundaries": {"meshes": [{"path": "../meshes/box.obj", "fluid": true}]}})");
    const clsph::Scene s = clsph::Scene::from_file(dir.file("scenes/drop.json"));
    REQUIRE(s.meshes.size() == 1);
    CHECK(s.meshes[0].path == std::filesystem::path(dir.file("meshes/box.obj")).lexically_normal().string());
    CHECK(s.build_particles().size() == 11 * 11 * 11);
    // The resolved scene names the mesh by its absolute path, so it reads back from anywhere.
    CHECK(clsph::Scene::from_json_text(s.to_json(), "copy.json").meshes[0].path == s.meshes[0].path);
}

TEST_CASE("run.cell_order: each order by name, written back by to_json only where not auto; another name is refused") {
    const std::string base = R"({"physics": {"dp": 0.05}, "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
            "fluid": [{"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}])";
    CHECK(clsph::Scene::from_json_text(base + "}", "plain.json").run.cell_order == clsph::CellOrder::automatic);
    // The default is not written: a scene's hash, which checkpoints check, is what it was before the key.
    CHECK(clsph::Scene::from_json_text(base + "}", "plain.json").to_json().find("cell_order") == std::string::npos);
    for (const auto order : {clsph::CellOrder::automatic, clsph::CellOrder::arrival, clsph::CellOrder::morton}) {
        const std::string name = clsph::cell_order_name(order);
        CAPTURE(name);
        const clsph::Scene s = clsph::Scene::from_json_text(base + R"(, "run": {"cell_order": ")" + name + "\"}}", "o.json");
        CHECK(s.run.cell_order == order);
        CHECK(clsph::Scene::from_json_text(s.to_json(), "back.json").run.cell_order == order);
        CHECK(clsph::cell_order_from_name(name) == order);
    }
    try {
        (void)clsph::Scene::from_json_text(base + R"(, "run": {"cell_order": "hilbert"}})", "bad.json");
        FAIL("an unknown order was accepted");
    } catch (const clsph::Error& e) {
        const std::string what = e.what();
        CAPTURE(what);
        CHECK(what.find("cell_order") != std::string::npos);
        CHECK(what.find("morton") != std::string::npos);  // the choices are listed
    }
    CHECK_THROWS_AS(clsph::cell_order_from_name("Morton"), clsph::Error);
}

TEST_CASE("run.list_buffer: read, written back only where not 0, and a value outside [0, 1] refused naming the key") {
    const std::string base = R"({"physics": {"dp": 0.05}, "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
            "fluid": [{"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}])";
    const clsph::Scene plain = clsph::Scene::from_json_text(base + "}", "plain.json");
    CHECK(plain.run.list_buffer == 0);
    CHECK(plain.to_json().find("list_buffer") == std::string::npos);  // the hash of older scenes stays
    const clsph::Scene s = clsph::Scene::from_json_text(base + R"(, "run": {"list_buffer": 0.125}})", "b.json");
    CHECK(s.run.list_buffer == 0.125);
    CHECK(clsph::Scene::from_json_text(s.to_json(), "back.json").run.list_buffer == 0.125);
    for (const char* bad : {"-0.1", "1.5", "\"wide\""}) {
        CAPTURE(bad);
        try {
            (void)clsph::Scene::from_json_text(base + R"(, "run": {"list_buffer": )" + bad + "}}", "bad.json");
            FAIL("accepted");
        } catch (const clsph::Error& e) {
            const std::string what = e.what();
            CAPTURE(what);
            CHECK(what.find("list_buffer") != std::string::npos);
        }
    }
}

TEST_CASE("run.interaction: every form by name, written back by to_json; another name is refused naming the key") {
    const std::string base = R"({"physics": {"dp": 0.05}, "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
            "fluid": [{"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}], "run": {"interaction": ")";
    for (const auto form : clsph::interaction_forms()) {
        const std::string name = clsph::interaction_name(form);
        CAPTURE(name);
        const clsph::Scene s = clsph::Scene::from_json_text(base + name + "\"}}", "forms.json");
        CHECK(s.run.interaction == form);
        CHECK(clsph::Scene::from_json_text(s.to_json(), "back.json").run.interaction == form);
    }
    try {
        (void)clsph::Scene::from_json_text(base + "cluster\"}}", "bad.json");
        FAIL("an unknown form was accepted");
    } catch (const clsph::Error& e) {
        const std::string what = e.what();
        CAPTURE(what);
        CHECK(what.find("interaction") != std::string::npos);
        CHECK(what.find("clusters") != std::string::npos);  // the choices are listed
    }
}
