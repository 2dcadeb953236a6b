// STL and PLY meshes: files written here, binary and ASCII, from the same cube and icosphere as an
// OBJ file, give exactly the same particles as the OBJ, for a boundary solid and a fluid fill;
// every hostile file is a SceneError naming it; scale, rotate and translate place a mesh.
#include "support.hpp"
#include "../support/skip.hpp"

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

namespace {

// Vertices hold float values, so that binary STL (float32 only) keeps them exactly.
struct Mesh {
    std::vector<std::array<double, 3>> v;
    std::vector<std::vector<int>> f;  // 0-based, polygons allowed
};

Mesh cube_quads() {
    return {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
            {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};
}

// The polygons fanned around their first vertex, as every reader does.
Mesh triangulated(const Mesh& m) {
    Mesh t{m.v, {}};
    for (const auto& f : m.f)
        for (std::size_t k = 1; k + 1 < f.size(); ++k) t.f.push_back({f[0], f[k], f[k + 1]});
    return t;
}

Mesh icosphere(int levels, double r) {
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    Mesh s;
    s.v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
           {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    s.f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
           {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> middle;
        auto mid = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            if (auto it = middle.find(key); it != middle.end()) return it->second;
            s.v.push_back({(s.v[a][0] + s.v[b][0]) / 2, (s.v[a][1] + s.v[b][1]) / 2, (s.v[a][2] + s.v[b][2]) / 2});
            return middle[key] = static_cast<int>(s.v.size() - 1);
        };
        std::vector<std::vector<int>> next;
        for (const auto& f : s.f) {
            const int a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
            next.push_back({f[0], a, c});
            next.push_back({f[1], b, a});
            next.push_back({f[2], c, b});
            next.push_back({a, b, c});
        }
        s.f = next;
    }
    for (auto& p : s.v) {
        const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (auto& c : p) c = static_cast<float>(c * r / n);
    }
    return s;
}

std::string obj_text(const Mesh& m) {
    std::ostringstream o;
    o.precision(17);
    for (const auto& p : m.v) o << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const auto& f : m.f) {
        o << 'f';
        for (int i : f) o << ' ' << i + 1;
        o << '\n';
    }
    return o.str();
}

void put32(std::string& s, std::uint32_t x) {
    for (int i = 0; i < 4; ++i) s += static_cast<char>(x >> (8 * i) & 0xff);
}
void put_float(std::string& s, float f) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    put32(s, bits);
}

// Binary STL of the triangulated mesh; the header begins with `header` (padded to 80 bytes).
std::string stl_binary(const Mesh& polygons, const std::string& header = "clsph test") {
    const Mesh m = triangulated(polygons);
    std::string s = header;
    s.resize(80, ' ');
    put32(s, static_cast<std::uint32_t>(m.f.size()));
    for (const auto& f : m.f) {
        for (int k = 0; k < 3; ++k) put_float(s, 0.0f);  // normal: ignored
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) put_float(s, static_cast<float>(m.v[f[c]][k]));
        s += std::string(2, '\0');
    }
    return s;
}

std::string stl_ascii(const Mesh& polygons) {
    const Mesh m = triangulated(polygons);
    std::ostringstream o;
    o.precision(17);
    o << "solid test mesh\n";
    for (const auto& f : m.f) {
        o << "  facet normal 0 0 0\n    outer loop\n";
        for (int c = 0; c < 3; ++c) o << "      vertex " << m.v[f[c]][0] << ' ' << m.v[f[c]][1] << ' ' << m.v[f[c]][2] << '\n';
        o << "    endloop\n  endfacet\n";
    }
    o << "endsolid test mesh\n";
    return o.str();
}

// PLY in `format`; coordinates float or double, an extra vertex property and an extra list
// before and after x y z, the face count as uchar or int, indices int or uint, and a skipped element.
struct PlyStyle {
    std::string format = "ascii";
    bool doubles = false, int_count = false, uint_index = false;
};

std::string ply(const Mesh& m, const PlyStyle& st) {
    const bool big = st.format == "binary_big_endian", ascii = st.format == "ascii";
    std::string s = "ply\nformat " + st.format + " 1.0\ncomment written by test_mesh_formats\n";
    s += "element vertex " + std::to_string(m.v.size()) + "\nproperty uchar red\n";
    const std::string real = st.doubles ? "double" : "float";
    s += "property " + real + " x\nproperty " + real + " y\nproperty " + real + " z\nproperty list uchar short extra\nproperty ushort flags\n";
    s += "element face " + std::to_string(m.f.size()) + "\nproperty list " + (st.int_count ? "int " : "uchar ") +
         (st.uint_index ? "uint" : "int") + " vertex_indices\nproperty float quality\n";
    s += "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
    auto bin = [&](std::uint64_t bits, int bytes) {
        for (int i = 0; i < bytes; ++i) s += static_cast<char>(bits >> (8 * (big ? bytes - 1 - i : i)) & 0xff);
    };
    auto real_value = [&](double x) {
        if (st.doubles) {
            std::uint64_t b;
            std::memcpy(&b, &x, 8);
            bin(b, 8);
        } else {
            const float f = static_cast<float>(x);
            std::uint32_t b;
            std::memcpy(&b, &f, 4);
            bin(b, 4);
        }
    };
    std::ostringstream o;
    o.precision(17);
    for (const auto& p : m.v) {
        if (ascii) {
            o << "7 " << p[0] << ' ' << p[1] << ' ' << p[2] << " 2 -1 5 3\n";
        } else {
            bin(7, 1);
            for (double c : p) real_value(c);
            bin(2, 1), bin(0xffff, 2), bin(5, 2), bin(3, 2);
        }
    }
    for (const auto& f : m.f) {
        if (ascii) {
            o << f.size();
            for (int i : f) o << ' ' << i;
            o << " 0.5\n";
        } else {
            bin(f.size(), st.int_count ? 4 : 1);
            for (int i : f) bin(static_cast<std::uint32_t>(i), 4);
            std::uint32_t half;
            const float h = 0.5f;
            std::memcpy(&half, &h, 4);
            bin(half, 4);
        }
    }
    if (ascii) {
        o << "0 1\n";
        s += o.str();
    } else {
        bin(0, 4), bin(1, 4);
    }
    return s;
}

struct Sampled {
    std::vector<clsph::Vec3> boundary, fluid;
};

Sampled sample(const std::string& path, double dp, bool fluid, int layers = 3, clsph::Vec3 translate = {0, 0, 0},
               clsph::Vec3 rotate = {0, 0, 0}, double scale = 1.0) {
    clsph::MeshObject m;
    m.path = path;
    m.fluid = fluid;
    m.layers = layers;
    m.scale = scale;
    m.translate = translate;
    m.rotate = rotate;
    Sampled s;
    clsph::scene::sample_mesh(m, dp, s.boundary, s.fluid);
    return s;
}

// Every format of `m` (written under `dir` as name.*) against the OBJ, boundary and fluid.
void check_formats_agree(const scene_test::TempDir& dir, const std::string& name, const Mesh& m, double dp,
                         clsph::Vec3 offset) {
    const std::string obj = dir.file(name + ".obj");
    scene_test::write_text(obj, obj_text(m));
    const Sampled fluid = sample(obj, dp, true, 3, offset), shell = sample(obj, dp, false, 2, offset);
    REQUIRE(fluid.fluid.size() > 100);
    REQUIRE(shell.boundary.size() > 100);
    std::vector<std::pair<std::string, std::string>> files = {
        {name + "_bin.stl", stl_binary(m)},
        {name + "_solid_header.STL", stl_binary(m, "solid but binary")},
        {name + "_ascii.stl", stl_ascii(m)},
    };
    for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"})
        for (int style = 0; style < 4; ++style) {
            PlyStyle st;
            st.format = format;
            st.doubles = style & 1;
            st.int_count = style & 2;
            st.uint_index = style == 1 || style == 2;
            files.push_back({name + "_" + format + std::to_string(style) + ".ply", ply(m, st)});
        }
    for (const auto& [file, bytes] : files) {
        CAPTURE(file);
        const std::string path = dir.file(file);
        scene_test::write_text(path, bytes);
        const Sampled f = sample(path, dp, true, 3, offset), b = sample(path, dp, false, 2, offset);
        CHECK(f.fluid == fluid.fluid);
        CHECK(b.boundary == shell.boundary);
        CHECK(b.fluid.empty());
    }
}

}  // namespace

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
