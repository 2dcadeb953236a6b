// The dam break's surge front against the experiment of Koshizuka & Oka (1996), shared by the
// validation and mdbc suites: a 2:1 column of width L released in a tank 4 L long.
#pragma once
#include "clsph/simulation.hpp"
#include "support/scenes.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace clsph::test {

// The validation dam break: a 4L tank (the front reaches 3.6 L by T = 3, so no far wall is needed).
inline Scene surge_dam_break(double L, double dp) { return dam_break_slice(L, dp, 4.0, x_min | z_min); }

// Rows (T, Z) of ../shared/data/dam_break_koshizuka_oka_1996.csv (or CLSPH_DATA_DIR).
inline std::vector<std::array<double, 2>> koshizuka_oka() {
    const char* env = std::getenv("CLSPH_DATA_DIR");  // where the build-time path does not exist
    const std::string path = std::string(env && *env ? env : CLSPH_SHARED_DATA) + "/dam_break_koshizuka_oka_1996.csv";
    std::ifstream in(path);
    REQUIRE_MESSAGE(in.good(), "cannot read " << path);
    std::vector<std::array<double, 2>> rows;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#' || line[0] == 'T') continue;
        std::istringstream ls(line);
        double t, z;
        char comma;
        if (ls >> t >> comma >> z) rows.push_back({t, z});
    }
    return rows;
}

// Runs `sim` (a surge_dam_break of width L) to each of the experiment's times up to T = 3 and
// returns the RMS relative error of the front position Z = x_front / L.
inline double surge_front_rms(Simulation& sim, double L) {
    const double g = 9.81;
    const auto data = koshizuka_oka();
    REQUIRE(data.size() >= 5);
    const double t_scale = std::sqrt(2 * g / L);
    double sum2 = 0;
    std::size_t n = 0;
    for (const auto& row : data) {
        const double T = row[0], Z = row[1];
        if (T > 3.0 + 1e-9) break;
        sim.run_until(T / t_scale);
        const auto p = sim.particles();
        double front = 0;
        for (std::size_t i = 0; i < p.size(); ++i)
            if (p.type[i] == ParticleType::fluid) front = std::max(front, p.position[i][0]);
        const double z = front / L;
        MESSAGE("T = " << T << ": Z = " << z << " (experiment " << Z << ")");
        sum2 += (z - Z) * (z - Z) / (Z * Z);
        ++n;
    }
    const double rms = std::sqrt(sum2 / double(n));
    MESSAGE("dam break: RMS relative error of the surge front " << rms * 100 << " % over " << n << " points, "
                                                                 << sim.info().step << " steps, "
                                                                 << sim.info().particles << " particles, "
                                                                 << sim.info().wall_seconds << " s");
    return rms;
}

}  // namespace clsph::test
