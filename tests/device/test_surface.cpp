// Marching cubes (kernels/marching_cubes.cl, host/src/surface/) against analytic level sets on
// every device: a sphere and a torus sampled as signed distances. The mesh is closed (every edge
// shared by exactly two triangles), oriented outwards, its area and enclosed volume within 1 % of
// the exact values on the finest grid, and equal to the plain C++ reference given the same field.
#include "clsph/error.hpp"
#include "clsph/mesh.hpp"
#include "clsph/simulation.hpp"
#include "surface/marching_cubes.hpp"
#include "surface/mc_table.hpp"
#include "support/scenes.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <functional>
#include <map>
#include <random>

using namespace clsph;
using namespace clsph::surface;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Sampled {
    SampleGrid grid;
    std::vector<float> values;
};

// The field f on a grid of `n` samples per axis covering [-extent, extent]^3, with a random offset
// of the grid (so the surface cuts cubes everywhere differently from run to run).
Sampled sample(const std::function<double(double, double, double)>& f, std::uint32_t n, double extent, std::mt19937_64& gen) {
    std::uniform_real_distribution<double> shift(-0.5, 0.5);
    Sampled s;
    s.grid.points = {n, n, n};
    s.grid.spacing = 2 * extent / (n - 1);
    for (auto& o : s.grid.origin) o = -extent + shift(gen) * s.grid.spacing;
    s.values.resize(s.grid.samples());
    for (std::uint32_t k = 0; k < n; ++k)
        for (std::uint32_t j = 0; j < n; ++j)
            for (std::uint32_t i = 0; i < n; ++i)
                s.values[i + n * (j + n * k)] = static_cast<float>(
                    f(s.grid.origin[0] + i * s.grid.spacing, s.grid.origin[1] + j * s.grid.spacing, s.grid.origin[2] + k * s.grid.spacing));
    return s;
}

struct Measures {
    double area = 0, volume = 0;
    std::size_t open_edges = 0, overused_edges = 0;
    std::size_t inward_normals = 0;
};

Measures measure(const Mesh& m) {
    Measures r;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;  // each directed edge once, its reverse once
    for (const auto& t : m.triangles) {
        const auto& a = m.positions[t[0]];
        const auto& b = m.positions[t[1]];
        const auto& c = m.positions[t[2]];
        const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
        const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
        const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        r.area += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        r.volume += (double(a[0]) * (double(b[1]) * c[2] - double(b[2]) * c[1]) - double(a[1]) * (double(b[0]) * c[2] - double(b[2]) * c[0]) +
                     double(a[2]) * (double(b[0]) * c[1] - double(b[1]) * c[0])) / 6.0;
        // the triangle's winding agrees with the vertices' outward normals
        const auto& na = m.normals[t[0]];
        if (n[0] * na[0] + n[1] * na[1] + n[2] * na[2] < 0) ++r.inward_normals;
        for (int e = 0; e < 3; ++e) ++directed[{t[e], t[(e + 1) % 3]}];
    }
    for (const auto& [edge, count] : directed) {
        const auto back = directed.find({edge.second, edge.first});
        if (count > 1) ++r.overused_edges;
        if (back == directed.end()) ++r.open_edges;
    }
    return r;
}

}  // namespace

TEST_SUITE("surface") {
TEST_CASE("the case table: every case closes its loops, the complement of a case mirrors it") {
    const auto& t = case_table();
    for (int cs = 0; cs < 256; ++cs) {
        // each edge used by the case's triangles is a crossing edge, and appears an even number of times
        std::map<int, int> uses;
        for (int k = 0; k < CLSPH_MC_CASE_ENTRIES && t[cs][k] != 255; ++k) ++uses[t[cs][k]];
        for (int e = 0; e < 12; ++e) {
            const auto c = edge_corners(e);
            const bool crosses = ((cs >> c[0]) & 1) != ((cs >> c[1]) & 1);
            CAPTURE(cs);
            CAPTURE(e);
            CHECK(crosses == (uses.count(e) > 0));
        }
    }
    CHECK(t[0][0] == 255);
    CHECK(t[255][0] == 255);
    // Each case alone, as the central cube of a 4^3 grid that is outside everywhere else: a closed
    // surface around its inside corners, oriented outwards (positive volume).
    SampleGrid g;
    g.points = {4, 4, 4};
    for (int cs = 1; cs < 256; ++cs) {
        std::vector<float> f(64, -1.0f);
        for (int c = 0; c < 8; ++c) {
            const auto o = corner_offset(c);
            f[(1 + o[0]) + 4 * ((1 + o[1]) + 4 * (1 + o[2]))] = ((cs >> c) & 1) ? 1.0f : -1.0f;
        }
        const Measures m = measure(marching_cubes_reference(f, g, 0.0f));
        CAPTURE(cs);
        CHECK(m.open_edges == 0);
        CHECK(m.overused_edges == 0);
        CHECK(m.volume > 0);
    }
}

TEST_CASE("marching cubes of a sphere and a torus: closed, outward, exact area and volume, as the CPU") {
    struct Shape {
        const char* name;
        std::function<double(double, double, double)> f;  // >= 0 inside
        double area, volume;
    };
    const double R = 0.7, r = 0.25, Rt = 0.55;
    const Shape shapes[] = {
        {"sphere", [&](double x, double y, double z) { return R - std::sqrt(x * x + y * y + z * z); }, 4 * kPi * R * R,
         4.0 / 3.0 * kPi * R * R * R},
        {"torus",
         [&](double x, double y, double z) {
             const double q = std::sqrt(x * x + y * y) - Rt;
             return r - std::sqrt(q * q + z * z);
         },
         4 * kPi * kPi * Rt * r, 2 * kPi * kPi * Rt * r * r},
    };
    auto gen = test::rng(1800);
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        MarchingCubes mc(*d);
        for (const auto& shape : shapes)
            for (const std::uint32_t n : {24u, 96u}) {
                CAPTURE(std::string(shape.name));
                CAPTURE(n);
                const Sampled s = sample(shape.f, n, 1.0, gen);
                auto field = d->alloc(s.values.size() * sizeof(float), "test field");
                d->write(field, s.values.data(), s.values.size());
                const Mesh m = mc.run(field, s.grid, 0.0f);
                const Mesh ref = marching_cubes_reference(s.values, s.grid, 0.0f);
                REQUIRE(m.triangles.size() == ref.triangles.size());
                REQUIRE(m.positions.size() == ref.positions.size());
                CHECK(m.triangles == ref.triangles);  // same welding, same order
                double worst = 0;
                for (std::size_t v = 0; v < m.positions.size(); ++v)
                    for (int k = 0; k < 3; ++k) worst = std::max(worst, double(std::abs(m.positions[v][k] - ref.positions[v][k])));
                CHECK(worst < 1e-5 * s.grid.spacing * n);  // float round-off of the interpolation
                const Measures got = measure(m);
                CHECK(got.open_edges == 0);
                CHECK(got.overused_edges == 0);
                CHECK(got.inward_normals == 0);
                MESSAGE(std::string(shape.name) << " at " << n << "^3: " << m.triangles.size() << " triangles, area " << got.area / shape.area
                                   << " and volume " << got.volume / shape.volume << " of the exact");
                const double tolerance = n >= 96 ? 0.01 : 0.05;
                CHECK(std::abs(got.area / shape.area - 1) < tolerance);
                CHECK(std::abs(got.volume / shape.volume - 1) < tolerance);
            }
    }
}

TEST_CASE("random fields: every case, the ambiguous ones included, meshes closed and consistently oriented") {
    // Random values inside, outside values on the border: closed surfaces of any topology, so all
    // 256 cases (and both readings of every ambiguous face) occur.
    auto gen = test::rng(1801);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    SampleGrid g;
    g.points = {14, 13, 12};
    std::vector<float> f(g.samples());
    std::vector<bool> seen(256, false);
    for (std::uint32_t k = 0; k < 12; ++k)
        for (std::uint32_t j = 0; j < 13; ++j)
            for (std::uint32_t i = 0; i < 14; ++i) {
                const bool border = i == 0 || j == 0 || k == 0 || i == 13 || j == 12 || k == 11;
                f[i + 14 * (j + 13 * k)] = border ? -1.0f : u(gen);
            }
    for (std::uint32_t k = 0; k + 1 < 12; ++k)
        for (std::uint32_t j = 0; j + 1 < 13; ++j)
            for (std::uint32_t i = 0; i + 1 < 14; ++i) {
                int cs = 0;
                for (int c = 0; c < 8; ++c) {
                    const auto o = corner_offset(c);
                    cs |= (f[(i + o[0]) + 14 * ((j + o[1]) + 13 * (k + o[2]))] >= 0.0f ? 1 : 0) << c;
                }
                seen[cs] = true;
            }
    MESSAGE(std::count(seen.begin(), seen.end(), true) << " of the 256 cases occur");
    const Mesh ref = marching_cubes_reference(f, g, 0.0f);
    const Measures r = measure(ref);
    CHECK(r.open_edges == 0);
    CHECK(r.overused_edges == 0);
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        MarchingCubes mc(*d);
        auto field = d->alloc(f.size() * sizeof(float), "test field");
        d->write(field, f.data(), f.size());
        const Mesh m = mc.run(field, g, 0.0f);
        CHECK(m.triangles == ref.triangles);
        const Measures got = measure(m);
        CHECK(got.open_edges == 0);
        CHECK(got.overused_edges == 0);
        CHECK(got.volume > 0);  // oriented outwards overall
    }
}

TEST_CASE("samples exactly at the iso level make no degenerate triangle") {
    // A plane through grid points: every sample of the middle layer equals iso.
    SampleGrid g;
    g.points = {6, 6, 6};
    std::vector<float> f(g.samples());
    for (std::uint32_t k = 0; k < 6; ++k)
        for (std::uint32_t j = 0; j < 6; ++j)
            for (std::uint32_t i = 0; i < 6; ++i) f[i + 6 * (j + 6 * k)] = 2.0f - static_cast<float>(k);
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        MarchingCubes mc(*d);
        auto field = d->alloc(f.size() * sizeof(float), "test field");
        d->write(field, f.data(), f.size());
        const Mesh m = mc.run(field, g, 0.0f);
        REQUIRE(!m.triangles.empty());
        const Measures got = measure(m);
        CHECK(got.area == doctest::Approx(25.0).epsilon(1e-3));  // the 5 x 5 plane, once
        for (const auto& t : m.triangles) {
            CHECK(t[0] != t[1]);
            CHECK(t[1] != t[2]);
            CHECK(t[0] != t[2]);
        }
    }
}
}

TEST_SUITE("surface") {
TEST_CASE("a mesh written as PLY reads back exactly; as VTP its arrays are where the header says") {
    auto gen = test::rng(1802);
    const Sampled s = sample([](double x, double y, double z) { return 0.6 - std::sqrt(x * x + y * y + z * z); }, 20, 1.0, gen);
    const Mesh m = marching_cubes_reference(s.values, s.grid, 0.0f);
    REQUIRE(!m.triangles.empty());
    const std::string dir = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp");
    const std::string ply = dir + "/clsph_test_mesh_" + std::to_string(test::seed()) + ".ply";
    write_ply(ply, m);
    const TriangleMesh back = read_ply(ply);
    CHECK(back.positions == m.positions);
    CHECK(back.normals == m.normals);
    CHECK(back.triangles == m.triangles);
    std::remove(ply.c_str());

    const std::string vtp = dir + "/clsph_test_mesh_" + std::to_string(test::seed()) + ".vtp";
    write_vtp(vtp, m);
    std::ifstream in(vtp, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::remove(vtp.c_str());
    CHECK(text.find("NumberOfPoints=\"" + std::to_string(m.positions.size()) + "\"") != std::string::npos);
    CHECK(text.find("NumberOfPolys=\"" + std::to_string(m.triangles.size()) + "\"") != std::string::npos);
    // appended blocks: normals, positions (12 B per vertex each), connectivity (12 B per triangle),
    // offsets (8 B per triangle), each after a UInt64 byte count
    const auto start = text.find("   _") + 4;
    const std::size_t payload = 4 * 8 + 24 * m.positions.size() + 20 * m.triangles.size();
    CHECK(text.size() == start + payload + std::string("\n  </AppendedData>\n</VTKFile>\n").size());
    std::uint64_t first = 0;
    std::memcpy(&first, &text[start], 8);
    CHECK(first == 12 * m.positions.size());
    CHECK_THROWS_AS(write_ply(dir + "/clsph_bad.ply", TriangleMesh{{{0, 0, 0}}, {}, {{0, 1, 2}}}), Error);
}
}

namespace {
}  // namespace

TEST_SUITE("surface") {
TEST_CASE("the free surface of a fluid block at rest: closed, its top flat at the right height") {
    const Scene scene = test::small_tank(0.3, 0.15);
    Options o;
    o.devices = test::device_spec(1);
    Simulation sim(scene, o);
    const TriangleMesh m = sim.surface();
    REQUIRE(m.triangles.size() > 100);
    const Measures got = measure(m);
    CHECK(got.open_edges == 0);
    CHECK(got.overused_edges == 0);
    CHECK(got.inward_normals == 0);
    // The top face, away from the walls: upward normals, at z = 0.15 within dp / 2, flat.
    const double dp = scene.physics.dp;
    double lo = 1e9, hi = -1e9;
    std::size_t top = 0;
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const auto& x = m.positions[v];
        if (m.normals[v][2] < 0.9 || x[0] < 3 * dp || x[0] > 0.3 - 3 * dp || x[1] < 3 * dp || x[1] > 0.1 - 3 * dp) continue;
        ++top;
        lo = std::min(lo, double(x[2]));
        hi = std::max(hi, double(x[2]));
    }
    // The right height: the top of the fluid's volume, half a spacing above its top layer.
    const Particles p = sim.particles();
    double top_layer = -1e9, fluid = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (p.type[i] == ParticleType::fluid) {
            top_layer = std::max(top_layer, p.position[i][2]);
            fluid += 1;
        }
    const double height = top_layer + dp / 2;
    MESSAGE(top << " top vertices between z = " << lo << " and " << hi << " (fluid top layer " << top_layer << ", dp " << dp << ")");
    REQUIRE(top > 50);
    CHECK(std::abs(lo - height) < dp / 2);
    CHECK(std::abs(hi - height) < dp / 2);
    CHECK(hi - lo < dp / 4);
    // The enclosed volume is the fluid's (dp^3 per particle) within 10 %: the fraction falls off
    // next to walls, whose particles are not fluid.
    MESSAGE("enclosed volume " << got.volume << " m^3, fluid particles' " << fluid * dp * dp * dp);
    CHECK(got.volume == doctest::Approx(fluid * dp * dp * dp).epsilon(0.10));
}

}

// Three devices of one OpenCL implementation (CTest runs this suite with POCL_DEVICES="pthread
// pthread pthread"): their particles are bitwise those of one device, so the surface must be too.
TEST_SUITE("multi_bitwise") {
TEST_CASE("the same scene meshed on one device and on three gives the same triangles") {
    REQUIRE(test::devices().size() >= 3);
    const Scene scene = test::small_tank(0.3, 0.15);
    Options one, three;
    one.devices = test::device_spec(1);
    three.devices = test::device_spec(3);
    Simulation a(scene, one), b(scene, three);
    for (int i = 0; i < 5; ++i) {
        a.step();
        b.step();
    }
    REQUIRE(b.shares().size() >= 2);
    const TriangleMesh ma = a.surface(), mb = b.surface();
    REQUIRE(ma.triangles.size() == mb.triangles.size());
    REQUIRE(ma.positions.size() == mb.positions.size());
    // Match every triangle of the three-device mesh to one of the one-device mesh with the same
    // three vertices within `tol` (a hash of centroids: vertex numbering and order may differ).
    // Samples next to a cut see the neighbour's ghosts, whose densities are those of the exchange
    // (one kick behind), so vertices there agree to round-off, not bitwise.
    const double tol = 1e-5 * scene.physics.dp, cell = 0.25 * scene.physics.dp;
    auto centroid = [](const TriangleMesh& m, const std::array<std::uint32_t, 3>& t) {
        std::array<double, 3> c{};
        for (auto v : t)
            for (std::size_t k = 0; k < 3; ++k) c[k] += m.positions[v][k] / 3.0;
        return c;
    };
    auto cell_of = [&](const std::array<double, 3>& c) {
        return std::array<long, 3>{std::lround(c[0] / cell), std::lround(c[1] / cell), std::lround(c[2] / cell)};
    };
    std::map<std::array<long, 3>, std::vector<std::size_t>> index;
    for (std::size_t t = 0; t < ma.triangles.size(); ++t) index[cell_of(centroid(ma, ma.triangles[t]))].push_back(t);
    auto same = [&](const std::array<std::uint32_t, 3>& ta, const std::array<std::uint32_t, 3>& tb) {
        for (auto vb : tb) {
            bool found = false;
            for (auto va : ta) {
                double d = 0;
                for (std::size_t k = 0; k < 3; ++k) d = std::max(d, double(std::abs(ma.positions[va][k] - mb.positions[vb][k])));
                found = found || d <= tol;
            }
            if (!found) return false;
        }
        return true;
    };
    std::size_t unmatched = 0;
    for (const auto& tb : mb.triangles) {
        const auto c = cell_of(centroid(mb, tb));
        bool found = false;
        for (long dz = -1; dz <= 1 && !found; ++dz)
            for (long dy = -1; dy <= 1 && !found; ++dy)
                for (long dx = -1; dx <= 1 && !found; ++dx) {
                    const auto it = index.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == index.end()) continue;
                    for (auto t : it->second) found = found || same(ma.triangles[t], tb);
                }
        unmatched += found ? 0 : 1;
    }
    MESSAGE(mb.triangles.size() << " triangles on three devices, " << unmatched << " without a twin on one device");
    CHECK(unmatched == 0);
}
}
