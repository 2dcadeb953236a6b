// The smallest program that runs clsph: a dam break built in code (no scene file), a few
// milliseconds of simulated time on the default devices, the particles read back and written as
// a VTU frame that ParaView opens. Everything here is the public API: clsph/*.hpp and clsph::clsph.
//
//   clsph-hello [OUT.vtu]      (default: clsph_hello.vtu in the system's temporary directory)
#include <clsph/error.hpp>
#include <clsph/io.hpp>
#include <clsph/scene.hpp>
#include <clsph/simulation.hpp>
#include <clsph/version.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

namespace {

// A water column 0.1 m wide and 0.2 m high at the end of a tank 0.4 m long, on a 1 cm lattice: a
// slice 12 particles deep, periodic in y (three kernel supports, the least a periodic axis takes),
// so there are no side walls: 2,400 fluid and 3,420 boundary particles.
clsph::Scene tiny_dam_break() {
    clsph::Scene scene;
    scene.name = "hello";
    scene.physics.dp = 0.01;  // every other physics parameter keeps its documented default
    scene.domain.min = {-0.04, 0.0, -0.04};  // room for the walls' 3 layers outside the tank
    scene.domain.max = {0.44, 0.12, 0.3};
    scene.domain.periodic = {false, true, false};

    clsph::BoxWalls tank;  // the floor and the two end walls; open at the top
    tank.min = {0.0, 0.0, 0.0};
    tank.max = {0.4, 0.11, 0.25};  // periodic: lattice rows end one dp before the period
    tank.faces = clsph::x_min | clsph::x_max | clsph::z_min;
    scene.walls.push_back(tank);

    clsph::FluidBlock column;  // starts at rest, hydrostatic
    column.min = {0.0, 0.0, 0.0};
    column.max = {0.1, 0.11, 0.2};
    scene.fluids.push_back(column);

    clsph::Probe base;
    base.name = "p_base";
    base.point = {0.05, 0.06, 0.02};  // at rest: rho0 g (0.2 - 0.02) = 1.77 kPa
    scene.probes.push_back(base);
    return scene;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string out =
        argc > 1 ? argv[1] : (std::filesystem::temp_directory_path() / "clsph_hello.vtu").string();
    try {
        const clsph::Scene scene = tiny_dam_break();
        scene.validate();  // the checks `clsph run` makes on a scene file, before any device work

        clsph::Options options;  // devices: $CLSPH_DEVICES, else every GPU, else every CPU device
        clsph::Simulation sim(scene, options);
        std::cout << "clsph " << clsph::version() << " on";
        for (const auto& d : sim.device_names()) std::cout << ' ' << d;
        std::cout << '\n';

        auto print_probes = [&sim] {
            for (const auto& probe : sim.sample_probes())  // computed on the device
                std::printf("probe %s at t = %.5f s: %.1f Pa\n", probe.name.c_str(), probe.time, probe.value);
        };
        print_probes();
        sim.run_until(0.005, [](const clsph::StepInfo& s) {
            if (s.step % 10 == 0)
                std::printf("step %llu: t = %.5f s, dt = %.2e s, max speed %.3f m/s\n",
                            static_cast<unsigned long long>(s.step), s.time, s.dt, s.max_speed);
        });
        print_probes();

        const clsph::Particles particles = sim.particles();  // host copy: ids, positions, velocities, rho, p
        clsph::write_vtu(out, particles);
        std::cout << particles.size() << " particles at t = " << sim.time() << " s written to " << out << '\n';
    } catch (const clsph::Error& e) {  // typed errors, each message in the user's terms
        std::cerr << "error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
