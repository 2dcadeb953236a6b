// What the mesh-format tests share: meshes written as OBJ, STL (binary, ASCII) and PLY (every
// style), and sampled into particles.
#pragma once
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

namespace mesh_test {

// Vertices hold float values, so that binary STL (float32 only) keeps them exactly.
struct Mesh {
    std::vector<std::array<double, 3>> v;
    std::vector<std::vector<int>> f;  // 0-based, polygons allowed
};

inline Mesh cube_quads() {
    return {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
            {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};
}

// The polygons fanned around their first vertex, as every reader does.
inline Mesh triangulated(const Mesh& m) {
    Mesh t{m.v, {}};
    for (const auto& f : m.f)
        for (std::size_t k = 1; k + 1 < f.size(); ++k) t.f.push_back({f[0], f[k], f[k + 1]});
    return t;
}

// An icosahedron subdivided `levels` times, its vertices pushed onto the sphere of radius r and, by
// default, rounded to float (binary STL holds nothing finer; the OBJ and PLY then hold the same).
inline Mesh icosphere(int levels, double r, bool float_vertices = true) {
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
        for (auto& c : p) c = float_vertices ? static_cast<float>(c * r / n) : c * r / n;
    }
    return s;
}

inline std::string obj_text(const Mesh& m) {
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

inline void put32(std::string& s, std::uint32_t x) {
    for (int i = 0; i < 4; ++i) s += static_cast<char>(x >> (8 * i) & 0xff);
}
inline void put_float(std::string& s, float f) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    put32(s, bits);
}

// Binary STL of the triangulated mesh; the header begins with `header` (padded to 80 bytes).
inline std::string stl_binary(const Mesh& polygons, const std::string& header = "clsph test") {
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

inline std::string stl_ascii(const Mesh& polygons) {
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

inline std::string ply(const Mesh& m, const PlyStyle& st) {
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

inline Sampled sample(const std::string& path, double dp, bool fluid, int layers = 3, clsph::Vec3 translate = {0, 0, 0},
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
inline void check_formats_agree(const scene_test::TempDir& dir, const std::string& name, const Mesh& m, double dp,
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

}  // namespace mesh_test
