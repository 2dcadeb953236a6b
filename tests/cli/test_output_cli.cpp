// Frames that scale (issue 20): --output-stride K and --output-box thin every frame and its CSV twin
// to the particles asked for, read back by clsph's own reader and checked against a full run's
// frames; clsph surface refuses thinned frames; bad values exit 1 naming the option. --compress
// writes zlib-compressed frames equal to the raw ones; --pieces a VTU per device and a .pvtu whose
// pieces hold every particle once (two pocl devices, else skipped with a message).
#include "support.hpp"
#include "../support/skip.hpp"

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
    // One device: two runs on several devices step different slabs (the balancer follows measured
    // times), so their frames would differ in order and in round-off.
    const std::vector<std::string> common = {"--devices", "0", "--until", "0.002", "--every", "0.002", "--csv"};
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

namespace {

// Bitwise equality by id (both frames sorted by id).
std::size_t differences(clsph::Particles a, clsph::Particles b) {
    auto sorted = [](const clsph::Particles& p) {
        std::vector<std::size_t> order(p.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return p.id[x] < p.id[y]; });
        return order;
    };
    if (a.size() != b.size()) return std::max(a.size(), b.size());
    const auto oa = sorted(a), ob = sorted(b);
    std::size_t wrong = 0;
    for (std::size_t k = 0; k < oa.size(); ++k) {
        const std::size_t i = oa[k], j = ob[k];
        wrong += a.id[i] != b.id[j] || a.type[i] != b.type[j] || a.position[i] != b.position[j] ||
                 a.velocity[i] != b.velocity[j] || a.density[i] != b.density[j] || a.pressure[i] != b.pressure[j];
    }
    return wrong;
}

}  // namespace

TEST_CASE("--compress: frames ParaView reads zlib-compressed, smaller, reading back as the raw frames") {
    const std::string raw = work_dir("compress_raw"), zlib = work_dir("compress_zlib");
    std::string log;
    const std::vector<std::string> common = {"--devices", "0", "--until", "0.004", "--every", "0.002"};
    REQUIRE(run(args({{"run", scene}, tiny, common, {"--out", raw}}), log) == 0);
    REQUIRE(run(args({{"run", scene}, tiny, common, {"--compress", "--out", zlib}}), log) == 0);
    INFO(log);
    const auto frames = clsph::read_pvd(raw + "/dam_break.pvd"), packed = clsph::read_pvd(zlib + "/dam_break.pvd");
    REQUIRE(frames.size() == 3);
    REQUIRE(packed.size() == frames.size());
    for (std::size_t f = 0; f < frames.size(); ++f) {
        CAPTURE(f);
        const std::string file = zlib + "/" + packed[f].file;
        CHECK(read_text(file).find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos);
        CHECK(fs::file_size(file) < fs::file_size(raw + "/" + frames[f].file));
        CHECK(differences(clsph::read_vtu(raw + "/" + frames[f].file), clsph::read_vtu(file)) == 0);
    }
}

// Needs two devices: POCL_DEVICES="basic pthread" (as scripts/test.sh sets it).
TEST_CASE("--pieces: one VTU per device and a .pvtu per frame, every particle exactly once, thinned as asked") {
    if (devices_picked("platform:pocl") < 2) {
        test_skip::skip("--pieces needs two pocl devices (POCL_DEVICES=\"basic pthread\"); this host has one");
        return;
    }
    const std::string whole = work_dir("pieces_whole"), split = work_dir("pieces_split"), thin = work_dir("pieces_thin");
    std::string log;
    // Static cuts, so that two runs step the same slabs the same way.
    const std::vector<std::string> common = {"--devices", "platform:pocl", "--balance", "static", "--until", "0.004",
                                             "--every", "0.002"};
    REQUIRE(run(args({{"run", scene}, tiny, common, {"--out", whole}}), log) == 0);
    REQUIRE(run(args({{"run", scene}, tiny, common, {"--pieces", "--compress", "--csv", "--out", split}}), log) == 0);
    REQUIRE(run(args({{"run", scene}, tiny, common, {"--pieces", "--output-stride", "3", "--out", thin}}), log) == 0);
    INFO(log);
    const auto frames = clsph::read_pvd(whole + "/dam_break.pvd"), pieced = clsph::read_pvd(split + "/dam_break.pvd"),
               thinned = clsph::read_pvd(thin + "/dam_break.pvd");
    REQUIRE(frames.size() == 3);
    REQUIRE(pieced.size() == frames.size());
    REQUIRE(thinned.size() == frames.size());
    for (std::size_t f = 0; f < frames.size(); ++f) {
        CAPTURE(f);
        CHECK(pieced[f].file == "frame_0000" + std::to_string(f) + ".pvtu");
        const std::string index = split + "/" + pieced[f].file;
        const auto sources = clsph::read_pvtu_sources(index);
        REQUIRE(sources.size() == 2);
        // Each piece a compressed VTU holding particles; together every particle exactly once.
        std::map<std::uint32_t, int> seen;
        for (const auto& s : sources) {
            const std::string piece = split + "/" + s;
            CHECK(read_text(piece).find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos);
            const clsph::Particles p = clsph::read_vtu(piece);
            CHECK(p.size() > 100);
            for (auto id : p.id) ++seen[id];
        }
        const clsph::Particles all = clsph::read_vtu(whole + "/" + frames[f].file);
        CHECK(seen.size() == all.size());
        std::size_t twice = 0, missing = 0;
        for (const auto& [id, count] : seen) twice += count != 1;
        for (auto id : all.id) missing += seen.count(id) == 0;
        CHECK(twice == 0);
        CHECK(missing == 0);
        // The index reads back as the single-file frame, and as the run's own CSV twin.
        const clsph::Particles joined = clsph::read_vtu(index);
        CHECK(differences(joined, all) == 0);
        CHECK(differences(joined, clsph::read_csv(split + "/frame_0000" + std::to_string(f) + ".csv")) == 0);
        // --output-stride applies to every piece.
        std::size_t want = 0;
        for (auto id : all.id) want += id % 3 == 0;
        std::size_t got = 0, wrong = 0;
        for (const auto& s : clsph::read_pvtu_sources(thin + "/" + thinned[f].file)) {
            const clsph::Particles p = clsph::read_vtu(thin + "/" + s);
            got += p.size();
            for (auto id : p.id) wrong += id % 3 != 0 || seen.count(id) == 0;
        }
        CHECK(got == want);
        CHECK(wrong == 0);
    }
    // clsph surface reads the pieced frames back.
    fs::remove(split + "/surface.pvd");
    REQUIRE(run({"surface", split, "--devices", "0"}, log) == 0);
    CHECK(clsph::read_pvd(split + "/surface.pvd").size() == frames.size());
}
