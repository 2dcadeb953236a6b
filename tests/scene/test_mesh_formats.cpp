// STL and PLY meshes: files written here, binary and ASCII, from the same cube and icosphere as an
// OBJ file, give exactly the same particles as the OBJ, for a boundary solid and a fluid fill;
// every hostile file is a SceneError naming it (placement, ghost nodes, the bunny:
// test_mesh_placement.cpp).
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

TEST_CASE("STL and PLY give the same particles as OBJ: a cube of quads and an icosphere") {
    scene_test::TempDir dir;
    check_formats_agree(dir, "cube", cube_quads(), 0.1, {0, 0, 0});
    check_formats_agree(dir, "cube_off", cube_quads(), 0.1, {0.05, 0.013, -0.021});
    check_formats_agree(dir, "sphere", icosphere(2, 1.0), 0.1, {0.0123, -0.0311, 0.0277});
    // ASCII STL in upper case with CRLF line ends, two solids; a PLY element with no properties
    // and an enormous count (nothing in the body): the same cube.
    const Mesh cube = cube_quads();
    const Sampled reference = sample(dir.file("cube.obj"), 0.1, true);
    std::string upper = stl_ascii(cube);
    const std::size_t half = upper.find("  facet", upper.size() / 2);
    upper.insert(half, "endsolid a\nsolid b\n");
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    std::string crlf;
    for (char c : upper) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    scene_test::write_text(dir.file("upper.stl"), crlf);
    CHECK(sample(dir.file("upper.stl"), 0.1, true).fluid == reference.fluid);
    std::string empty_element = ply(cube, {});
    empty_element.insert(empty_element.find("end_header"), "element nothing 9223372036854775807\n");
    scene_test::write_text(dir.file("empty_element.ply"), empty_element);
    CHECK(sample(dir.file("empty_element.ply"), 0.1, true).fluid == reference.fluid);

    // The welded STL cube: 8 vertices, 12 triangles, closed.
    const std::string path = dir.file("cube_bin.stl");
    const auto mesh = clsph::scene::read_closed_mesh(path);
    CHECK(mesh.vertices.size() == 8);
    CHECK(mesh.triangles.size() == 12);
}

TEST_CASE("the format comes from the extension, confirmed by the content") {
    scene_test::TempDir dir;
    const std::string off = dir.file("cube.off");
    scene_test::write_text(off, obj_text(cube_quads()));
    CHECK(error_of([&] { sample(off, 0.1, true); }) == off + ": not a mesh format clsph reads (the name must end in .obj, .stl or .ply)");
    const std::string ply_as_stl = dir.file("cube_ply.stl");
    scene_test::write_text(ply_as_stl, ply(cube_quads(), {}));
    CHECK(error_of([&] { sample(ply_as_stl, 0.1, true); }) == ply_as_stl + ": this is a PLY file, not STL (name it .ply)");
    const std::string stl_as_ply = dir.file("cube_stl.PLY");
    scene_test::write_text(stl_as_ply, stl_ascii(cube_quads()));
    CHECK(error_of([&] { sample(stl_as_ply, 0.1, true); }) ==
          stl_as_ply + ": not a PLY file: it does not start with the line 'ply' (an STL file? name it .stl)");

    // The scene refuses the extension before any particle is made.
    clsph::Scene s;
    s.domain.min = {-1, -1, -1};
    s.domain.max = {2, 2, 2};
    clsph::MeshObject m;
    m.path = off;
    m.fluid = true;
    s.meshes.push_back(m);
    CHECK(error_of([&] { s.validate(); }) ==
          "boundaries.meshes[0].path: cannot read \"" + off + "\": not a mesh format clsph reads (the name must end in .obj, .stl or .ply)");
}

TEST_CASE("hostile STL files are errors naming the file and the triangle") {
    scene_test::TempDir dir;
    const Mesh cube = cube_quads();
    const auto write = [&](const std::string& name, const std::string& bytes) {
        const std::string path = dir.file(name);
        scene_test::write_text(path, bytes);
        return path;
    };
    const auto error = [](const std::string& path) { return error_of([&] { sample(path, 0.1, true); }); };

    // Triangle 2, vertex 3, y (bytes 84 + 50 + 12 normal + 24 + 4).
    std::string bin = stl_binary(cube);
    std::string nan = bin;
    const float qnan = std::nanf("");
    std::memcpy(&nan[84 + 50 + 12 + 24 + 4], &qnan, 4);
    const std::string nan_path = write("nan.stl", nan);
    CHECK(error(nan_path) == nan_path + ": triangle 2: vertex 3 is not finite (y = nan)");
    std::string inf = bin;
    const float pinf = INFINITY;
    std::memcpy(&inf[84 + 12], &pinf, 4);
    const std::string inf_path = write("inf.stl", inf);
    CHECK(error(inf_path) == inf_path + ": triangle 1: vertex 1 is not finite (x = inf)");
    std::string huge = bin;
    const float big = 1e30f;
    std::memcpy(&huge[84 + 50 * 11 + 12 + 8], &big, 4);
    const std::string huge_path = write("huge.stl", huge);
    CHECK(error(huge_path) == huge_path + ": triangle 12: vertex 1 has a coordinate beyond 1e9 (z = 1.00000002e+30)");

    const std::string truncated = write("truncated.stl", bin.substr(0, bin.size() - 10));
    CHECK(error(truncated) == truncated + ": binary STL: the header declares 12 triangles, 84 + 50 n = 684 bytes, but the "
                                          "file has 674 (truncated, or a wrong count)");
    std::string wrong = bin;
    wrong[80] = static_cast<char>(0xff), wrong[81] = static_cast<char>(0xff), wrong[82] = static_cast<char>(0xff), wrong[83] = 0x7f;
    const std::string wrong_count = write("count.stl", wrong);
    CHECK(error(wrong_count) == wrong_count + ": binary STL: the header declares 2147483647 triangles, 84 + 50 n = "
                                              "107374182434 bytes, but the file has 684 (truncated, or a wrong count)");
    const std::string solid_truncated = write("solid_truncated.stl", stl_binary(cube, "solid x").substr(0, 300));
    CHECK(error(solid_truncated).find(solid_truncated + ": line ") == 0);
    CHECK(error(solid_truncated).find("its header declares 12 triangles, 84 + 50 n = 684 bytes, but it has 300: truncated, or a wrong count") != std::string::npos);
    const std::string tiny = write("tiny.stl", "abc");
    CHECK(error(tiny) == tiny + ": not an STL file: it does not start with 'solid' (ASCII STL) and has 3 bytes, fewer than "
                                "the 84 of a binary STL's header");
    const std::string empty = write("empty.stl", stl_binary(Mesh{}));
    CHECK(error(empty) == empty + ": the mesh has no faces (no triangle with 3 distinct vertices)");

    // ASCII.
    const std::string ascii = stl_ascii(cube);
    std::string a = ascii;
    a.replace(a.find("vertex 0 0 0"), 12, "vertex 0 nan 0");
    const std::string a_nan = write("a_nan.stl", a);
    CHECK(error(a_nan) == a_nan + ": triangle 1 (line 4): vertex 1 is not finite (y = nan)");
    a = ascii;
    a.replace(a.find("vertex 0 0 0"), 12, "vertex 0 zero 0");
    const std::string a_bad = write("a_bad.stl", a);
    CHECK(error(a_bad) == a_bad + ": line 4: 'zero' is not a number");
    const std::string a_cut = write("a_cut.stl", ascii.substr(0, ascii.size() / 2));
    CHECK(error(a_cut).find(a_cut + ": line ") == 0);
    const std::string a_end = write("a_end.stl", ascii.substr(0, ascii.rfind("endsolid")));
    CHECK(error(a_end) == a_end + ": line 85: the file ends before 'endsolid' (truncated?)");
    a = ascii;
    const auto third = a.find("vertex", a.find("vertex", a.find("vertex") + 1) + 1);
    a.erase(third, a.find('\n', third) - third);
    const std::string a_two = write("a_two.stl", a);
    CHECK(error(a_two) == a_two + ": line 7: expected 'vertex x y z' (a triangle has 3 vertices)");

    // Open: the cube without its last triangle, as fluid and as a boundary.
    Mesh open = triangulated(cube);
    open.f.pop_back();
    const std::string open_path = write("open.stl", stl_binary(open));
    const std::string not_closed = open_path + ": the mesh is not closed: 3 of 18 edges are not shared by exactly two "
                                               "triangles (inside and outside are only defined for a closed, watertight surface)";
    CHECK(error(open_path) == not_closed);
    CHECK(error_of([&] { sample(open_path, 0.1, false); }) == not_closed);
    const std::string missing = dir.file("missing.stl");
    CHECK(error(missing) == missing + ": cannot open mesh: No such file or directory");
}

TEST_CASE("hostile PLY files are errors naming the file and the element") {
    scene_test::TempDir dir;
    const Mesh cube = cube_quads();
    const auto write = [&](const std::string& name, const std::string& bytes) {
        const std::string path = dir.file(name);
        scene_test::write_text(path, bytes);
        return path;
    };
    const auto error = [](const std::string& path) { return error_of([&] { sample(path, 0.1, true); }); };
    PlyStyle le;
    le.format = "binary_little_endian";
    const std::string bin = ply(cube, le), ascii = ply(cube, {});
    const std::size_t body = bin.find("end_header\n") + 11;
    const std::size_t header_lines = 17;

    // Vertex 3's y: after red (1) and x (4); a vertex is 1 + 12 + 1 + 4 + 2 = 20 bytes.
    std::string nan = bin;
    const float qnan = std::nanf("");
    std::memcpy(&nan[body + 3 * 20 + 5], &qnan, 4);
    const std::string nan_path = write("nan.ply", nan);
    CHECK(error(nan_path) == nan_path + ": vertex 3 is not finite (y = nan)");
    std::string a = ascii;
    a.replace(a.find("7 1 1 1 "), 8, "7 1 1 inf ");
    const std::string a_inf = write("a_inf.ply", a);
    CHECK(error(a_inf) == a_inf + ": line " + std::to_string(header_lines + 7) + ": vertex 6 is not finite (z = inf)");

    a = ascii;
    a.replace(a.find("4 2 3 7 6"), 9, "4 2 3 7 9");
    const std::string range = write("range.ply", a);
    CHECK(error(range) == range + ": line " + std::to_string(header_lines + 13) + ": face 4: vertex index 9 is out of range (the file has 8 vertices)");
    a = ascii;
    a.replace(a.find("4 2 3 7 6"), 9, "4 2 3 -7 6");
    const std::string negative = write("negative.ply", a);
    CHECK(error(negative).find("face 4: vertex index -7 is out of range") != std::string::npos);
    a = ascii;
    a.replace(a.find("4 2 3 7 6"), 9, "2 2 3");
    const std::string two = write("two.ply", a);
    CHECK(error(two) == two + ": line " + std::to_string(header_lines + 13) + ": face 4 has 2 vertices (a face needs at least 3)");
    a = ascii;
    a.replace(a.find("7 1 1 1 "), 8, "7 1 one 1 ");
    const std::string word = write("word.ply", a);
    CHECK(error(word) == word + ": line " + std::to_string(header_lines + 7) + ": vertex 6: 'one' is not a number");

    // Truncated: inside the last element, and so short that the counts cannot fit.
    const std::string cut = write("cut.ply", bin.substr(0, bin.size() - 2));
    CHECK(error(cut) == cut + ": the file ends inside edge 0 (truncated, or a count in the header is too large)");
    const std::string cut_face = write("cut_face.ply", bin.substr(0, bin.size() - 20));
    CHECK(error(cut_face) == cut_face + ": face 5: a list of 4 items, more than the rest of the file holds (truncated, or a wrong count)");
    std::string many = bin;
    many.replace(many.find("element vertex 8"), 16, "element vertex 800000000");
    const std::string many_path = write("many.ply", many);
    CHECK(error(many_path).find(many_path + ": the header declares 800000000 vertex, 6 face, 1 edge, at least ") == 0);
    CHECK(error(many_path).find("truncated, or a wrong count") != std::string::npos);
    std::string huge_list = bin;
    huge_list.replace(huge_list.find("list uchar int vertex_indices"), 29, "list uint int vertex_indices");
    // The first face's count read as uint32: 4 | (0 << 8) ... the next index bytes make it large.
    const std::string list_path = write("list.ply", huge_list);
    CHECK(error(list_path).find(list_path + ": face 0") == 0);
    std::string fewer = bin;
    fewer.replace(fewer.find("element edge 1"), 14, "element edge 0");
    const std::string fewer_path = write("fewer.ply", fewer);
    CHECK(error(fewer_path) == fewer_path + ": 8 bytes follow the last element the header declares (a count in the header is too small?)");
    a = ascii;
    a.replace(a.find("element edge 1"), 14, "element edge 0");
    const std::string a_fewer = write("a_fewer.ply", a);
    CHECK(error(a_fewer) == a_fewer + ": line " + std::to_string(header_lines + 15) + ": the file goes on after the last element the header declares (a count in the header is too small?)");

    // Headers.
    const std::string no_end = write("no_end.ply", ascii.substr(0, ascii.find("end_header")));
    CHECK(error(no_end) == no_end + ": the PLY header has no 'end_header' line (truncated?)");
    a = ascii;
    a.replace(a.find("format ascii 1.0"), 16, "format utf8 1.0");
    const std::string format = write("format.ply", a);
    CHECK(error(format) == format + ": header line 2: 'utf8' is not a PLY format (ascii, binary_little_endian, binary_big_endian)");
    a = ascii;
    a.replace(a.find("property float z"), 16, "property float w");
    const std::string no_z = write("no_z.ply", a);
    CHECK(error(no_z) == no_z + ": the vertex element has no property 'z'");
    a = ascii;
    a.replace(a.find("property uchar red"), 18, "property quad red");
    const std::string type = write("type.ply", a);
    CHECK(error(type) == type + ": header line 5: 'quad' is not a PLY type");
    const std::string points = write("points.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n");
    CHECK(error(points) == points + ": the mesh has no faces (the PLY header declares no 'face' element)");

    // Open, as fluid and as a boundary.
    Mesh open = triangulated(cube);
    open.f.pop_back();
    const std::string open_path = write("open.ply", ply(open, le));
    const std::string not_closed = open_path + ": the mesh is not closed: 3 of 18 edges are not shared by exactly two "
                                               "triangles (inside and outside are only defined for a closed, watertight surface)";
    CHECK(error(open_path) == not_closed);
    CHECK(error_of([&] { sample(open_path, 0.1, false); }) == not_closed);
}

