// Meshes placed (scale, rotate, translate), their mDBC ghost nodes, and the Stanford bunny: the
// same from OBJ, STL and PLY (the formats themselves: test_mesh_formats.cpp).
#include "support.hpp"
#include "../support/skip.hpp"
#include "mesh_writers.hpp"
#include "clsph/scene.hpp"
#include "scene/ghost_nodes.hpp"
#include "scene/mesh.hpp"
#include "scene/mesh_formats.hpp"

#include <algorithm>
#include <cctype>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <sstream>
#include <vector>

using scene_test::error_of;
using namespace mesh_test;

TEST_CASE("scale, rotate (x, then y, then z, in degrees) and translate place a mesh") {
    clsph::MeshObject m;
    m.scale = 2;
    m.rotate = {90, 90, 0};
    m.translate = {10, 0, 0};
    clsph::scene::TriangleMesh mesh;
    mesh.vertices = {{0, 1, 0}};
    clsph::scene::place_mesh(mesh, m);
    // (0, 1, 0) * 2 = (0, 2, 0); about x by 90: (0, 0, 2); about y by 90: (2, 0, 0); + translate.
    CHECK(mesh.vertices[0] == clsph::Vec3{12, 0, 0});
    m.rotate = {0, 0, 45};
    m.scale = 1;
    m.translate = {0, 0, 0};
    mesh.vertices = {{1, 0, 0}};
    clsph::scene::place_mesh(mesh, m);
    CHECK(mesh.vertices[0][0] == doctest::Approx(std::sqrt(0.5)));
    CHECK(mesh.vertices[0][1] == doctest::Approx(std::sqrt(0.5)));
    CHECK(mesh.vertices[0][2] == 0);

    // A unit cube turned a quarter about z and moved back holds the same points as the cube.
    scene_test::TempDir dir;
    const std::string path = dir.file("cube.stl");
    scene_test::write_text(path, stl_binary(cube_quads()));
    CHECK(sample(path, 0.1, true, 3, {1, 0, 0}, {0, 0, 90}).fluid == sample(path, 0.1, true).fluid);
    CHECK(sample(path, 0.1, true, 3, {0, 1, 1}, {-270, 180, 0}).fluid.size() == 11 * 11 * 11);
    // Scaled by 2 and turned 45 degrees about z: the lattice points of the turned square prism.
    const auto turned = sample(path, 0.1, true, 3, {0, 0, 0}, {0, 0, 45}, 2.0).fluid;
    const double r = std::sqrt(0.5);
    for (const auto& p : turned) {
        const double u = r * (p[0] + p[1]), v = r * (p[1] - p[0]);  // back into the cube's frame
        REQUIRE(u >= -1e-6);
        REQUIRE(u <= 2 + 1e-6);
        REQUIRE(v >= -1e-6);
        REQUIRE(v <= 2 + 1e-6);
    }
    CHECK(std::abs(static_cast<double>(turned.size()) / (8.0 / 0.001) - 1.0) < 0.15);  // surface points count as inside

    // The JSON key, written back by to_json.
    scene_test::write_text(dir.file("drop.json"),
                           R"({"physics": {"dp": 0.1, "c0": 20}, "domain": {"min": [-1, -1, -1], "max": [2, 2, 2]},
                               "boundaries": {"meshes": [{"path": "cube.stl", "fluid": true, "rotate": [0, 0, 90], "translate": [1, 0, 0]}]}})");
    const clsph::Scene s = clsph::Scene::from_file(dir.file("drop.json"));
    CHECK(s.meshes[0].rotate == clsph::Vec3{0, 0, 90});
    CHECK(s.build_particles().size() == 11 * 11 * 11);
    CHECK(clsph::Scene::from_json_text(s.to_json(), "copy.json").meshes[0].rotate == clsph::Vec3{0, 0, 90});
}

TEST_CASE("mDBC ghost nodes of a mesh solid are the same from OBJ, STL and PLY") {
    scene_test::TempDir dir;
    const Mesh cube = cube_quads();
    scene_test::write_text(dir.file("solid.obj"), obj_text(cube));
    scene_test::write_text(dir.file("solid.stl"), stl_binary(cube));
    PlyStyle be;
    be.format = "binary_big_endian";
    scene_test::write_text(dir.file("solid.ply"), ply(cube, be));
    std::vector<std::vector<std::array<float, 3>>> offsets;
    std::vector<std::size_t> counts;
    for (const char* name : {"solid.obj", "solid.stl", "solid.ply"}) {
        const std::string json = std::string(R"({"physics": {"dp": 0.1, "c0": 20}, "domain": {"min": [-1, -1, -1], "max": [3, 3, 3]},
            "fluid": [{"min": [1.3, 0, 0], "max": [1.8, 1, 1]}],
            "boundaries": {"method": "mdbc", "meshes": [{"path": ")") + dir.file(name) +
                                 R"(", "layers": 2, "rotate": [0, 0, 90], "translate": [1, 0, 0]}]}})";
        const clsph::Scene s = clsph::Scene::from_json_text(json, name);
        const clsph::Particles p = s.build_particles();
        counts.push_back(p.size());
        offsets.push_back(clsph::scene::ghost_node_offsets(s, p));
    }
    CHECK(counts[0] == 6 * 11 * 11 + 11 * 11 * 11 - 7 * 7 * 7);
    CHECK(counts[1] == counts[0]);
    CHECK(counts[2] == counts[0]);
    CHECK(offsets[1] == offsets[0]);
    CHECK(offsets[2] == offsets[0]);
    std::size_t mirrored = 0;
    for (const auto& o : offsets[0]) mirrored += o != std::array<float, 3>{0, 0, 0};
    CHECK(mirrored == 11 * 11 * 11 - 7 * 7 * 7);
}

TEST_CASE("the Stanford bunny of glmark2-data as ASCII STL and double PLY fills as its OBJ does") {
    const std::string bunny = "/usr/share/glmark2/models/bunny.obj";
    if (!std::filesystem::exists(bunny)) {
        test_skip::skip(bunny + " is absent (apt-get install glmark2-data)");
        return;
    }
    // Its coordinates are decimal text, not floats: ASCII STL at 17 digits and PLY of doubles keep
    // them exactly (binary STL would round them to float). The STL's welded vertices are the OBJ's
    // distinct positions (the OBJ repeats some along texture seams).
    const clsph::scene::TriangleMesh obj = clsph::scene::read_obj(bunny);
    Mesh m;
    for (const auto& v : obj.vertices) m.v.push_back({v[0], v[1], v[2]});
    for (const auto& t : obj.triangles) m.f.push_back({static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])});
    scene_test::TempDir dir;
    scene_test::write_text(dir.file("bunny.stl"), stl_ascii(m));
    PlyStyle st;
    st.format = "binary_little_endian";
    st.doubles = true;
    scene_test::write_text(dir.file("bunny.ply"), ply(m, st));
    const Sampled reference = sample(bunny, 0.01, true, 3, {0.25, 0.25, 0.355}, {90, 0, 0}, 0.2);
    MESSAGE("bunny at dp 0.01, stood up: " << reference.fluid.size() << " fluid points");
    CHECK(reference.fluid.size() > 10000);
    CHECK(sample(dir.file("bunny.stl"), 0.01, true, 3, {0.25, 0.25, 0.355}, {90, 0, 0}, 0.2).fluid == reference.fluid);
    CHECK(sample(dir.file("bunny.ply"), 0.01, true, 3, {0.25, 0.25, 0.355}, {90, 0, 0}, 0.2).fluid == reference.fluid);
    CHECK(clsph::scene::read_closed_mesh(dir.file("bunny.stl")).vertices.size() <= obj.vertices.size());
}
