// The OBJ reader and the mesh sampler: the input is an OBJ file. Every input must end in a mesh (and
// its particles) or a clsph::SceneError naming the file and line, never a crash, a sanitizer
// report or an allocation beyond what the file's size justifies.
#include "clsph/error.hpp"
#include "scene/mesh.hpp"
#include "scene/mesh_obj.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // read_obj takes a path, as a scene names its meshes: the input goes to a file first.
    static const std::string path = "/tmp/clsph-fuzz-obj-" + std::to_string(getpid()) + ".obj";
    if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
        if (size) std::fwrite(data, 1, size, f);
        std::fclose(f);
    } else {
        return 0;
    }
    try {
        const clsph::scene::TriangleMesh mesh = clsph::scene::read_obj(path);
        (void)clsph::scene::count_open_edges(mesh);
        // A closed mesh is sampled at a dp that gives at most ~20^3 lattice points.
        clsph::MeshObject m;
        m.path = path;
        m.fluid = mesh.triangles.size() % 2 == 0;
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
