// Frames that scale (issue 20, in part): --output-stride K and --output-box thin every frame and its
// CSV twin to the particles asked for, read back by clsph's own reader and checked against a full
// run's frames; clsph surface refuses thinned frames; bad values exit 1 naming the option.
#include "support.hpp"

#include <clsph/error.hpp>

#include <doctest/doctest.h>

#include <fstream>
#include <map>

using namespace cli_test;

TEST_CASE("--output-stride and --output-box: frames and CSV hold exactly the particles asked for") {
    const std::string full = work_dir("output_full"), thin = work_dir("output_thin");
    std::string log;
    const std::vector<std::string> common = {"--until", "0.004", "--every", "0.002", "--csv"};
    REQUIRE(run(args({{"run", scene}, tiny, common, {"--out", full}}), log) == 0);
    // Every 3rd particle by id, inside the lower half of the column (walls and fluid).
    const std::vector<double> box = {-0.01, 0.0, -0.01, 0.1, 0.2, 0.15};
    REQUIRE(run(args({{"run", scene}, tiny, common,
                      {"--output-stride", "3", "--output-box", "-0.01", "0", "-0.01", "0.1", "0.2", "0.15", "--out", thin}}),
                log) == 0);
    INFO(log);
    const auto frames = clsph::read_pvd(full + "/dam_break.pvd"), thinned = clsph::read_pvd(thin + "/dam_break.pvd");
    REQUIRE(frames.size() == 3);
    REQUIRE(thinned.size() == frames.size());
    for (std::size_t f = 0; f < frames.size(); ++f) {
        CAPTURE(f);
        const clsph::Particles all = clsph::read_vtu(full + "/" + frames[f].file);
        const clsph::Particles got = clsph::read_vtu(thin + "/" + thinned[f].file);
        std::map<std::uint32_t, std::array<double, 3>> want;
        for (std::size_t i = 0; i < all.size(); ++i) {
            const auto& x = all.position[i];
            if (all.id[i] % 3 == 0 && x[0] >= box[0] && x[1] >= box[1] && x[2] >= box[2] && x[0] <= box[3] &&
                x[1] <= box[4] && x[2] <= box[5])
                want[all.id[i]] = x;
        }
        CHECK(want.size() > 50);
        CHECK(want.size() < all.size() / 4);  // it thinned
        REQUIRE(got.size() == want.size());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < got.size(); ++i) {
            const auto it = want.find(got.id[i]);
            wrong += it == want.end() || !(near(it->second[0], got.position[i][0]) && near(it->second[2], got.position[i][2]));
        }
        CHECK(wrong == 0);
        // The VTK header says as much, and the CSV twin holds the same rows.
        const std::string text = read_text(thin + "/" + thinned[f].file);
        CHECK(text.find("NumberOfPoints=\"" + std::to_string(want.size()) + "\"") != std::string::npos);
        const std::string csv = thin + "/" + thinned[f].file.substr(0, thinned[f].file.size() - 4) + ".csv";
        CHECK(read_csv_rows(csv).size() == want.size() + 1);  // and its header
    }
    // A surface from thinned frames would be wrong: refused, naming the option.
    CHECK(run({"surface", thin}, log) == 1);
    CHECK(log.find("--output-stride") != std::string::npos);
}

TEST_CASE("--output-stride and --output-box: unusable values exit 1 naming the option, nothing written") {
    std::string log;
    const std::string out = work_dir("output_bad");
    CHECK(run(args({{"run", scene}, tiny, {"--output-stride", "0", "--out", out}}), log) == 1);
    CHECK(log.find("--output-stride") != std::string::npos);
    CHECK(run(args({{"run", scene}, tiny, {"--output-box", "0", "0", "0", "0", "1", "1", "--out", out}}), log) == 1);
    CHECK(log.find("--output-box") != std::string::npos);
    CHECK(run(args({{"run", scene}, tiny, {"--output-box", "0", "0", "0", "1", "--out", out}}), log) == 1);
    CHECK(!std::filesystem::exists(out));
}

TEST_CASE("--fields: frames and CSV hold only the arrays asked for, the same values as a full frame's") {
    const std::string full = work_dir("fields_full"), some = work_dir("fields_some");
    std::string log;
    const std::vector<std::string> common = {"--until", "0.002", "--every", "0.002", "--csv"};
    REQUIRE(run(args({{"run", scene}, tiny, common, {"--out", full}}), log) == 0);
    REQUIRE(run(args({{"run", scene}, tiny, common, {"--fields", "id,pressure", "--out", some}}), log) == 0);
    INFO(log);
    const auto frames = clsph::read_pvd(some + "/dam_break.pvd");
    REQUIRE(frames.size() == 2);
    const std::string file = some + "/" + frames.back().file;
    const std::string text = read_text(file);
    CHECK(text.find("Name=\"pressure\"") != std::string::npos);
    CHECK(text.find("Name=\"velocity\"") == std::string::npos);
    CHECK(text.find("Name=\"density\"") == std::string::npos);
    CHECK(text.find("Name=\"type\"") == std::string::npos);
    // The strict reader names what is missing; with `present` the frame reads back.
    std::string error;
    try {
        (void)clsph::read_vtu(file);
    } catch (const clsph::Error& e) {
        error = e.what();
    }
    CHECK(error.find("no array named type") != std::string::npos);
    clsph::FrameFields present;
    const clsph::Particles got = clsph::read_vtu(file, &present);
    CHECK(present.id);
    CHECK(present.pressure);
    CHECK_FALSE(present.velocity);
    CHECK_FALSE(present.density);
    CHECK_FALSE(present.type);
    const clsph::Particles all = clsph::read_vtu(full + "/" + frames.back().file);
    REQUIRE(got.size() == all.size());
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < got.size(); ++i)
        wrong += got.id[i] != all.id[i] || got.pressure[i] != all.pressure[i] || got.position[i] != all.position[i];
    CHECK(wrong == 0);
    const auto rows = read_csv_rows(file.substr(0, file.size() - 4) + ".csv");
    REQUIRE(rows.size() == all.size() + 1);
    CHECK(rows[0] == std::vector<std::string>{"id", "x", "y", "z", "p"});
    // Unknown fields are refused before anything is written; surfaces refuse such frames.
    const std::string bad = work_dir("fields_bad");
    CHECK(run(args({{"run", scene}, tiny, {"--fields", "id,vorticity", "--out", bad}}), log) == 1);
    CHECK(log.find("--fields: unknown field \"vorticity\"") != std::string::npos);
    CHECK(!std::filesystem::exists(bad));
    CHECK(run({"surface", some}, log) == 1);
    CHECK(log.find("--fields") != std::string::npos);
}
