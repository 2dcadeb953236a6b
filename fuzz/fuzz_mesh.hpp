// The body of the mesh-reader fuzz targets (fuzz_stl, fuzz_ply): the input, written to a file
// with the given extension, must end in a mesh (and its particles) or a clsph::SceneError naming
// the file, never a crash, a sanitizer report or an allocation beyond what the file's size justifies.
#pragma once
#include "clsph/error.hpp"
#include "scene/mesh.hpp"
#include "scene/mesh_formats.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

inline int fuzz_mesh_file(const std::uint8_t* data, std::size_t size, const char* extension) {
    // The readers take a path, as a scene names its meshes: the input goes to a file first.
    static const std::string path = "/tmp/clsph-fuzz-mesh-" + std::to_string(getpid()) + extension;
    if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
        if (size) std::fwrite(data, 1, size, f);
        std::fclose(f);
    } else {
        return 0;
    }
    try {
        const clsph::scene::TriangleMesh mesh = clsph::scene::read_mesh(path);
        (void)clsph::scene::count_open_edges(mesh);
        // A closed mesh is sampled at a dp that gives at most ~20^3 lattice points, turned a little
        // on one input in three so that place_mesh's rotation runs too.
        clsph::MeshObject m;
        m.path = path;
        m.fluid = mesh.triangles.size() % 2 == 0;
        if (mesh.triangles.size() % 3 == 0) m.rotate = {10, 20, 30};
        clsph::Vec3 lo = mesh.vertices[0], hi = mesh.vertices[0];
        for (const auto& v : mesh.vertices)
            for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], v[k]), hi[k] = std::max(hi[k], v[k]);
        const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
        if (extent > 0 && mesh.vertices.size() < 5000) {
            std::vector<clsph::Vec3> boundary, fluid;
            clsph::scene::sample_mesh(m, extent / 20.0, boundary, fluid);
        }
    } catch (const clsph::SceneError&) {
    }
    return 0;
}
