// OBJ meshes sampled onto the dp lattice: inside-point counts of a cube and an icosphere, boundary
// layers, the OBJ forms we accept, and the errors for meshes we cannot use.
#include "support.hpp"
#include "mesh_writers.hpp"

#include "scene/mesh.hpp"
#include "scene/mesh_obj.hpp"
#include "../support/skip.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

using mesh_test::sample;
using scene_test::error_of;

namespace {

const char* cube_obj =
    "# unit cube, triangles\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
    "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";

// Volume enclosed by the polyhedron (divergence theorem over its triangles).
double volume(const mesh_test::Mesh& s) {
    double v = 0;
    for (const auto& f : s.f) {
        const auto &a = s.v[f[0]], &b = s.v[f[1]], &c = s.v[f[2]];
        v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return std::abs(v) / 6.0;
}

}  // namespace

TEST_CASE("a unit cube holds the lattice points of a closed unit box") {
    scene_test::TempDir dir;
    const std::string path = dir.file("cube.obj");
    scene_test::write_text(path, cube_obj);
    // On the lattice: faces included, as for a solid box.
    CHECK(sample(path, 0.1, true).fluid.size() == 11 * 11 * 11);
    // Off the lattice by half a spacing: points 0.1 ... 1.0 on each axis.
    CHECK(sample(path, 0.1, true, 3, {0.05, 0.05, 0.05}).fluid.size() == 10 * 10 * 10);
    // Scaled: a 2 m cube at dp 0.25.
    CHECK(sample(path, 0.25, true, 3, {0, 0, 0}, {0, 0, 0}, 2.0).fluid.size() == 9 * 9 * 9);
    // Boundary layers: the points less than 2 dp deep, like a SolidBox with 2 layers.
    const mesh_test::Sampled shell = sample(path, 0.1, false, 2);
    CHECK(shell.fluid.empty());
    CHECK(shell.boundary.size() == 11 * 11 * 11 - 7 * 7 * 7);
    // Every point is on the lattice.
    for (const auto& p : shell.boundary)
        for (double c : p) REQUIRE(std::abs(c / 0.1 - std::round(c / 0.1)) < 1e-9);
}

TEST_CASE("quads, v/vt/vn indices and negative indices read as the same cube") {
    scene_test::TempDir dir;
    const std::string path = dir.file("cube_quads.obj");
    scene_test::write_text(path,
                           "mtllib cube.mtl\no cube\n"
                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\r\n"
                           "vt 0 0\nvn 0 0 1\ns off\n"
                           "f 1/1/1 4/1/1 3/1/1 2/1/1\nf 5//1 6//1 7//1 8//1\n"
                           "f -8 -7 -3 -4   # 1 2 6 5\n"
                           "f 2/1 3/1 7/1 6/1\nf 3 4 8 7\nf 4 1 5 8\n");
    const clsph::scene::TriangleMesh mesh = clsph::scene::read_obj(path);
    CHECK(mesh.vertices.size() == 8);
    CHECK(mesh.triangles.size() == 12);
    CHECK(clsph::scene::count_open_edges(mesh).open == 0);
    CHECK(sample(path, 0.1, true).fluid.size() == 11 * 11 * 11);
}

TEST_CASE("an icosphere holds its volume in lattice points") {
    scene_test::TempDir dir;
    const std::string path = dir.file("icosphere.obj");
    const mesh_test::Mesh s = mesh_test::icosphere(3, 1.0, false);
    scene_test::write_text(path, mesh_test::obj_text(s));
    const double dp = 0.05, v = volume(s);
    const double filled = static_cast<double>(sample(path, dp, true).fluid.size());
    const double expected = v / (dp * dp * dp);
    MESSAGE("icosphere (1280 triangles, r = 1) at dp 0.05: " << filled << " points, volume / dp^3 = " << expected);
    CHECK(std::abs(filled / expected - 1.0) < 0.02);

    // Off-centre and off-lattice: the same count within the same tolerance.
    const double moved = static_cast<double>(sample(path, dp, true, 3, {0.0123, -0.0311, 0.0277}).fluid.size());
    CHECK(std::abs(moved / expected - 1.0) < 0.02);

    // Boundary shell of 3 layers: about the volume between the sphere and one 3 dp smaller.
    const double pi = std::acos(-1.0);
    const double r = std::cbrt(3.0 * v / (4.0 * pi)), t = 3 * dp;
    const double shell_expected = 4.0 / 3.0 * pi * (r * r * r - (r - t) * (r - t) * (r - t)) / (dp * dp * dp);
    const double shell = static_cast<double>(sample(path, dp, false, 3).boundary.size());
    MESSAGE("3-layer shell: " << shell << " points, expected about " << shell_expected);
    CHECK(std::abs(shell / shell_expected - 1.0) < 0.05);
}

TEST_CASE("meshes we cannot use give errors naming the file") {
    scene_test::TempDir dir;
    const std::string open = dir.file("open.obj");
    // The cube without its last triangle: that triangle's 3 edges are left with one neighbour.
    std::string text = cube_obj;
    text = text.substr(0, text.rfind("f 4 5 8"));
    scene_test::write_text(open, text);
    CHECK(error_of([&] { sample(open, 0.1, true); }) ==
          open + ": the mesh is not closed: 3 of 18 edges are not shared by exactly two triangles "
                 "(inside and outside are only defined for a closed, watertight surface)");

    const std::string out_of_range = dir.file("range.obj");
    scene_test::write_text(out_of_range, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
    CHECK(error_of([&] { sample(out_of_range, 0.1, true); }) ==
          out_of_range + ": line 5: vertex index 9 is out of range (the file has 3 vertices)");

    const std::string before_first = dir.file("negative.obj");
    scene_test::write_text(before_first, "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n");
    CHECK(error_of([&] { sample(before_first, 0.1, true); }) ==
          before_first + ": line 3: vertex index -3 reaches before the first vertex");

    const std::string no_faces = dir.file("points.obj");
    scene_test::write_text(no_faces, "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    CHECK(error_of([&] { sample(no_faces, 0.1, true); }).find(no_faces + ": the mesh has no faces") == 0);

    const std::string bad_number = dir.file("bad.obj");
    scene_test::write_text(bad_number, "v 0 0 zero\n");
    CHECK(error_of([&] { sample(bad_number, 0.1, true); }) == bad_number + ": line 1: 'zero' is not a number");

    const std::string missing = dir.file("missing.obj");
    CHECK(error_of([&] { sample(missing, 0.1, true); }) == missing + ": cannot open mesh: No such file or directory");
    const std::string bunny = "/usr/share/glmark2/models/no_such_bunny.obj";
    CHECK(error_of([&] { sample(bunny, 0.1, true); }).find("apt-get install glmark2-data") != std::string::npos);
}

TEST_CASE("the Stanford bunny of glmark2-data is a closed mesh") {
    const std::string bunny = "/usr/share/glmark2/models/bunny.obj";
    if (!std::filesystem::exists(bunny)) {
        test_skip::skip(bunny + " is absent (apt-get install glmark2-data)");
        return;
    }
    const auto mesh = clsph::scene::read_closed_obj(bunny);
    CHECK(mesh.vertices.size() == 34835);
    CHECK(mesh.triangles.size() == 69666);
}
