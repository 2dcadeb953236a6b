#include "surface/marching_cubes.hpp"

#include "cl/kernel_args.hpp"
#include "clsph/error.hpp"
#include "device/primitives_launch.hpp"
#include "surface/mc_table.hpp"

#include <algorithm>
#include <cmath>

namespace clsph::surface {
using device::ensure_capacity;

namespace {
void check_grid(const SampleGrid& g) {
    for (auto n : g.points)
        if (n < 2) throw Error("marching cubes: the sample grid needs at least 2 samples per axis");
    if (!(g.spacing > 0) || !std::isfinite(g.spacing)) throw Error("marching cubes: the sample spacing must be positive");
    if (3.0 * static_cast<double>(g.samples()) > 4.0e9) throw Error("marching cubes: the sample grid is too large");
}
}  // namespace

MarchingCubes::MarchingCubes(cl_rt::Device& device)
    : device_(device), scan_(device, device::Scan::Config{0, 0, "surface.scan"}), wg_(device.work_group_size(128)) {
    edges_k_ = device.kernel("marching_cubes.cl", "mc_edges", "");
    vertices_k_ = device.kernel("marching_cubes.cl", "mc_vertices", "");
    cubes_k_ = device.kernel("marching_cubes.cl", "mc_cubes", "");
    triangles_k_ = device.kernel("marching_cubes.cl", "mc_triangles", "");
    const auto& t = case_table();
    table_ = device.alloc(sizeof(t), "marching cubes table");
    device.write(table_, t[0].data(), 256 * std::size_t{CLSPH_MC_CASE_ENTRIES});
}

Mesh MarchingCubes::run(const cl_rt::Buffer& field, const SampleGrid& grid, float iso) {
    check_grid(grid);
    return run_blocks(field, grid.points, grid.origin, grid.spacing, {{0, 0, 0}}, iso).mesh;
}

BlockMeshes MarchingCubes::run_blocks(const cl_rt::Buffer& field, std::array<std::uint32_t, 3> points,
                                      const std::array<double, 3>& origin, double spacing,
                                      const std::vector<std::array<std::int32_t, 3>>& block_at, float iso) {
    BlockMeshes out;
    const std::size_t blocks = block_at.size();
    if (blocks == 0) return out;
    std::vector<cl_int> at(4 * blocks, 0);
    for (std::size_t b = 0; b < blocks; ++b)
        for (std::size_t k = 0; k < 3; ++k) at[4 * b + k] = block_at[b][k];
    auto at_buf = device_.alloc(at.size() * sizeof(cl_int), "surface block positions");
    device_.write(at_buf, at.data(), at.size());
    const DeviceBlockMeshes d = run_blocks_device(field, points, origin, spacing, at_buf, blocks, iso);
    Mesh& mesh = out.mesh;
    if (d.vertices > 0) {
        std::vector<float> p(4 * d.vertices), q(4 * d.vertices);
        device_.read(d.position, p.data(), p.size());
        device_.read(d.normal, q.data(), q.size());
        out.edge_of_vertex.resize(d.vertices);
        device_.read(d.edge_of_vertex, out.edge_of_vertex.data(), d.vertices);
        mesh.positions.resize(d.vertices);
        mesh.normals.resize(d.vertices);
        for (std::size_t v = 0; v < d.vertices; ++v) {
            mesh.positions[v] = {p[4 * v], p[4 * v + 1], p[4 * v + 2]};
            mesh.normals[v] = {q[4 * v], q[4 * v + 1], q[4 * v + 2]};
        }
    }
    if (d.triangles > 0) {
        std::vector<cl_uint> t(3 * d.triangles);
        device_.read(d.triangle_vertices, t.data(), t.size());
        mesh.triangles.resize(d.triangles);
        for (std::size_t k = 0; k < d.triangles; ++k) mesh.triangles[k] = {t[3 * k], t[3 * k + 1], t[3 * k + 2]};
    }
    return out;
}

DeviceBlockMeshes MarchingCubes::run_blocks_device(const cl_rt::Buffer& field, std::array<std::uint32_t, 3> points,
                                                   const std::array<double, 3>& origin, double spacing,
                                                   const cl_rt::Buffer& block_at, std::size_t blocks, float iso) {
    SampleGrid one;
    one.points = points;
    one.spacing = spacing;
    check_grid(one);
    DeviceBlockMeshes out;
    if (blocks == 0) return out;
    const std::size_t per = one.samples(), points_all = per * blocks, edges = 3 * points_all;
    const std::size_t cubes = std::size_t{points[0] - 1} * (points[1] - 1) * (points[2] - 1) * blocks;
    if (static_cast<double>(edges) > 4.0e9) throw Error("marching cubes: too many blocks in one batch");
    const cl_uint4 n{{points[0], points[1], points[2], cl_rt::checked_uint(blocks, "surface blocks")}};
    // The crossing flags are scanned in place into each edge's vertex index (n + 1 elements).
    out.vertex_of = device_.alloc((edges + 1) * sizeof(cl_uint), "surface vertex indices");
    set_args(edges_k_, n, iso, field, out.vertex_of);
    device_.launch("surface.edges", edges_k_, points_all, wg_);
    out.vertices = scan_.exclusive_total(out.vertex_of, out.vertex_of, edges);
    if (out.vertices > 0) {
        const cl_float4 o{{static_cast<float>(origin[0]), static_cast<float>(origin[1]), static_cast<float>(origin[2]), 0.0f}};
        out.position = device_.alloc(out.vertices * 4 * sizeof(float), "surface positions");
        out.normal = device_.alloc(out.vertices * 4 * sizeof(float), "surface normals");
        out.edge_of_vertex = device_.alloc(out.vertices * sizeof(cl_uint), "surface vertex edges");
        set_args(vertices_k_, n, iso, o, block_at, static_cast<float>(spacing), cl_rt::checked_uint(out.vertices), field,
                 out.vertex_of, out.position, out.normal, out.edge_of_vertex);
        device_.launch("surface.vertices", vertices_k_, edges, wg_);
    }
    auto per_cube = device_.alloc((cubes + 1) * sizeof(cl_uint), "surface triangles per cube");
    set_args(cubes_k_, n, iso, field, table_, per_cube);
    device_.launch("surface.cubes", cubes_k_, cubes, wg_);
    out.triangles = scan_.exclusive_total(per_cube, per_cube, cubes);
    if (out.triangles > 0) {
        out.triangle_vertices = device_.alloc(out.triangles * 3 * sizeof(cl_uint), "surface triangles");
        set_args(triangles_k_, n, iso, cl_rt::checked_uint(out.triangles), field, table_, per_cube, out.vertex_of,
                 out.triangle_vertices);
        device_.launch("surface.triangles", triangles_k_, cubes, wg_);
    }
    return out;
}

void MarchingCubes::run_blocks_capacity(const cl_rt::Buffer& field, std::array<std::uint32_t, 3> points,
                                        const std::array<double, 3>& origin, double spacing,
                                        const cl_rt::Buffer& block_at, std::size_t blocks, std::size_t vertices,
                                        std::size_t triangles, float iso, DeviceBlockMeshes& out) {
    SampleGrid one;
    one.points = points;
    one.spacing = spacing;
    check_grid(one);
    const std::size_t per = one.samples(), points_all = per * blocks, edges = 3 * points_all;
    const std::size_t cubes = std::size_t{points[0] - 1} * (points[1] - 1) * (points[2] - 1) * blocks;
    if (static_cast<double>(edges) > 4.0e9) throw Error("marching cubes: too many blocks in one batch");
    const cl_uint4 n{{points[0], points[1], points[2], cl_rt::checked_uint(blocks, "surface blocks")}};
    out.vertices = vertices;
    out.triangles = triangles;
    ensure_capacity(device_, out.vertex_of, (edges + 1) * sizeof(cl_uint), "surface vertex indices");
    ensure_capacity(device_, out.position, std::max<std::size_t>(vertices, 1) * 4 * sizeof(float), "surface positions");
    ensure_capacity(device_, out.normal, std::max<std::size_t>(vertices, 1) * 4 * sizeof(float), "surface normals");
    ensure_capacity(device_, out.edge_of_vertex, std::max<std::size_t>(vertices, 1) * sizeof(cl_uint), "surface vertex edges");
    ensure_capacity(device_, out.first_triangle, (cubes + 1) * sizeof(cl_uint), "surface triangles per cube");
    ensure_capacity(device_, out.triangle_vertices, std::max<std::size_t>(triangles, 1) * 3 * sizeof(cl_uint), "surface triangles");
    if (blocks == 0) return;
    set_args(edges_k_, n, iso, field, out.vertex_of);
    device_.launch("surface.edges", edges_k_, points_all, wg_);
    scan_.exclusive(out.vertex_of, out.vertex_of, edges);
    const cl_float4 o{{static_cast<float>(origin[0]), static_cast<float>(origin[1]), static_cast<float>(origin[2]), 0.0f}};
    set_args(vertices_k_, n, iso, o, block_at, static_cast<float>(spacing), cl_rt::checked_uint(vertices), field,
             out.vertex_of, out.position, out.normal, out.edge_of_vertex);
    device_.launch("surface.vertices", vertices_k_, edges, wg_);
    set_args(cubes_k_, n, iso, field, table_, out.first_triangle);
    device_.launch("surface.cubes", cubes_k_, cubes, wg_);
    scan_.exclusive(out.first_triangle, out.first_triangle, cubes);
    set_args(triangles_k_, n, iso, cl_rt::checked_uint(triangles), field, table_, out.first_triangle, out.vertex_of,
             out.triangle_vertices);
    device_.launch("surface.triangles", triangles_k_, cubes, wg_);
}

Mesh marching_cubes_reference(const std::vector<float>& f, const SampleGrid& g, float iso) {
    check_grid(g);
    const std::size_t nx = g.points[0], ny = g.points[1], nz = g.points[2];
    if (f.size() != g.samples()) throw Error("marching cubes: field size does not match the grid");
    auto at = [&](std::size_t i, std::size_t j, std::size_t k) { return i + nx * (j + ny * k); };
    auto value = [&](std::size_t i, std::size_t j, std::size_t k) { return f[at(i, j, k)]; };
    const std::size_t dims[3] = {nx, ny, nz};
    std::vector<std::uint32_t> vertex_of(3 * g.samples(), UINT32_MAX);
    Mesh mesh;
    auto grad = [&](std::size_t i, std::size_t j, std::size_t k) {
        std::array<double, 3> out{};
        const std::size_t c[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
            std::size_t lo[3] = {i, j, k}, hi[3] = {i, j, k};
            if (c[a] > 0) lo[a] = c[a] - 1;
            if (c[a] + 1 < dims[a]) hi[a] = c[a] + 1;
            out[a] = (double(value(hi[0], hi[1], hi[2])) - value(lo[0], lo[1], lo[2])) / (double(hi[a] - lo[a]) * g.spacing);
        }
        return out;
    };
    for (std::size_t k = 0; k < nz; ++k)
        for (std::size_t j = 0; j < ny; ++j)
            for (std::size_t i = 0; i < nx; ++i)
                for (int a = 0; a < 3; ++a) {
                    std::size_t e[3] = {i, j, k};
                    e[a] += 1;
                    if (e[a] >= dims[a]) continue;
                    const double f0 = value(i, j, k), f1 = value(e[0], e[1], e[2]);
                    if ((f0 >= iso) == (f1 >= iso)) continue;
                    const double t = std::clamp((iso - f0) / (f1 - f0), 1e-4, 1.0 - 1e-4);
                    std::array<float, 3> x{};
                    const std::size_t c[3] = {i, j, k};
                    for (int d = 0; d < 3; ++d) x[d] = static_cast<float>(g.origin[d] + g.spacing * (double(c[d]) + (d == a ? t : 0.0)));
                    const auto g0 = grad(i, j, k), g1 = grad(e[0], e[1], e[2]);
                    std::array<double, 3> gr{};
                    for (int d = 0; d < 3; ++d) gr[d] = g0[d] + t * (g1[d] - g0[d]);
                    const double len = std::sqrt(gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]);
                    std::array<float, 3> nrm{};
                    for (int d = 0; d < 3; ++d) nrm[d] = len > 0 ? static_cast<float>(-gr[d] / len) : 0.0f;
                    vertex_of[3 * at(i, j, k) + static_cast<std::size_t>(a)] = static_cast<std::uint32_t>(mesh.positions.size());
                    mesh.positions.push_back(x);
                    mesh.normals.push_back(nrm);
                }
    const auto& table = case_table();
    for (std::size_t k = 0; k + 1 < nz; ++k)
        for (std::size_t j = 0; j + 1 < ny; ++j)
            for (std::size_t i = 0; i + 1 < nx; ++i) {
                int cs = 0;
                for (int c = 0; c < 8; ++c) {
                    const auto o = corner_offset(c);
                    cs |= (value(i + o[0], j + o[1], k + o[2]) >= iso ? 1 : 0) << c;
                }
                for (int t = 0; t < CLSPH_MC_MAX_TRIANGLES && table[cs][3 * t] != 255; ++t) {
                    std::array<std::uint32_t, 3> tri{};
                    for (int v = 0; v < 3; ++v) {
                        const int e = table[cs][3 * t + v];
                        const auto lo = corner_offset(edge_corners(e)[0]);
                        const int axis = e < 4 ? 0 : e < 8 ? 1 : 2;
                        tri[v] = vertex_of[3 * at(i + lo[0], j + lo[1], k + lo[2]) + static_cast<std::size_t>(axis)];
                    }
                    mesh.triangles.push_back(tri);
                }
            }
    return mesh;
}

}  // namespace clsph::surface
