#include "surface_command.hpp"

#include "run_dir.hpp"
#include "surface_output.hpp"

#include <clsph/error.hpp>
#include <clsph/io.hpp>
#include <clsph/scene.hpp>
#include <clsph/simulation.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace clsph::app {

int surface_command(const SurfaceArgs& args) {
    const std::string record = args.dir + "/run.json";
    const Scene scene = scene_of_run(args.dir, "clsph surface");
    nlohmann::json run;
    {
        std::ifstream in(record);
        in >> run;
    }
    // Frames thinned by --output-stride or --output-box hold a part of the fluid: its surface
    // would be a wrong one (the run's own --surface meshes every particle).
    if (run.contains("command_line") && run["command_line"].is_array()) {
        const auto& argv = run["command_line"];
        for (std::size_t i = 0; i < argv.size(); ++i) {
            const std::string a = argv[i].is_string() ? argv[i].get<std::string>() : std::string();
            const bool stride = a == "--output-stride" && i + 1 < argv.size() && argv[i + 1] != "1";
            const bool fields = a == "--fields" && i + 1 < argv.size() && argv[i + 1] != "all";
            if (stride || fields || a == "--output-box" || a.rfind("--output-stride=", 0) == 0 ||
                a.rfind("--output-box=", 0) == 0 || a.rfind("--fields=", 0) == 0)
                throw Error("clsph " + std::string(args.render ? "render" : "surface") + ": the frames in " + args.dir +
                            " hold part of the particles or of their data (" + a + "); a surface needs them all (clsph run --surface " +
                            "meshes every particle while it runs)");
        }
    }
    const std::string pvd = frames_pvd(args.dir);
    if (pvd.empty()) throw Error("clsph surface: no frame collection (.pvd) in " + args.dir);
    const auto frames = read_pvd(pvd);
    if (frames.empty()) throw Error(pvd + ": lists no frame");
    SurfaceOptions so;
    so.spacing = args.spacing;
    SurfaceOutput out(args.dir, 0, args.ply, so, args.render);
    Options opts;
    opts.devices = args.devices;
    for (const auto& f : frames) {
        const Particles p = read_vtu(args.dir + "/" + f.file);
        Simulation sim(scene, p, opts);
        const TriangleMesh mesh = sim.surface(so);
        out.write(f.time, mesh, sim);
        std::cout << "t = " << f.time << " s: " << mesh.triangles.size() << " triangles\n";
    }
    std::cout << "clsph " << (args.render ? "render" : "surface") << ": " << out.written() << " surfaces"
              << (args.render ? " and images" : "") << " in " << args.dir << "; open " << out.collection_path() << " in ParaView\n";
    if (args.video) std::cout << out.make_video() << '\n';
    return 0;
}

}  // namespace clsph::app
