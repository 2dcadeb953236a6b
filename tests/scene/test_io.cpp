// Output files: VTU and CSV frames read back equal to the particles written; the .pvd lists
// every frame with its time; errors name the path and the OS error.
#include "support.hpp"

#include <clsph/io.hpp>

#include <cstring>
#include <random>

using scene_test::error_of;

namespace {

clsph::Particles random_particles(std::size_t n, std::mt19937& rng) {
    std::uniform_real_distribution<double> x(-5.0, 5.0);
    std::uniform_real_distribution<float> v(-3.0f, 3.0f), rho(900.0f, 1100.0f), p(-1e4f, 1e5f);
    std::uniform_int_distribution<std::uint32_t> id(0, 4000000000u);
    clsph::Particles out;
    for (std::size_t i = 0; i < n; ++i)
        out.push_back(id(rng), rng() % 2 ? clsph::ParticleType::boundary : clsph::ParticleType::fluid,
                      {x(rng), x(rng) * 1e-7, x(rng) * 1e3}, {v(rng), v(rng), v(rng) * 1e-6f}, rho(rng), p(rng));
    return out;
}

// Bit-for-bit equality (positions in double, the rest in float, ids and types exact).
void check_equal(const clsph::Particles& a, const clsph::Particles& b) {
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        CAPTURE(i);
        REQUIRE(a.id[i] == b.id[i]);
        REQUIRE(a.type[i] == b.type[i]);
        REQUIRE(std::memcmp(&a.position[i], &b.position[i], sizeof a.position[i]) == 0);
        REQUIRE(std::memcmp(&a.velocity[i], &b.velocity[i], sizeof a.velocity[i]) == 0);
        REQUIRE(std::memcmp(&a.density[i], &b.density[i], sizeof(float)) == 0);
        REQUIRE(std::memcmp(&a.pressure[i], &b.pressure[i], sizeof(float)) == 0);
    }
}

bool no_temporary_files(const scene_test::TempDir& dir) {
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
        if (e.path().extension() == ".tmp") return false;
    return true;
}

}  // namespace

TEST_CASE("VTU frames with chosen fields: the arrays written read back, the others reported missing") {
    std::mt19937 rng(scene_test::fresh_seed());
    scene_test::TempDir dir;
    const clsph::Particles p = random_particles(1000 + rng() % 5000, rng);
    for (int mask = 0; mask < 32; ++mask) {
        CAPTURE(mask);
        clsph::FrameFields f;
        f.id = mask & 1, f.type = mask & 2, f.velocity = mask & 4, f.density = mask & 8, f.pressure = mask & 16;
        clsph::write_vtu(dir.file("frame.vtu"), p, f);
        clsph::FrameFields present;
        const clsph::Particles q = clsph::read_vtu(dir.file("frame.vtu"), &present);
        CHECK(present.id == f.id);
        CHECK(present.type == f.type);
        CHECK(present.velocity == f.velocity);
        CHECK(present.density == f.density);
        CHECK(present.pressure == f.pressure);
        REQUIRE(q.size() == p.size());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < p.size(); ++i) {
            wrong += std::memcmp(&p.position[i], &q.position[i], sizeof p.position[i]) != 0;
            wrong += f.id && p.id[i] != q.id[i];
            wrong += f.type && p.type[i] != q.type[i];
            wrong += f.velocity && std::memcmp(&p.velocity[i], &q.velocity[i], sizeof p.velocity[i]) != 0;
            wrong += f.density && std::memcmp(&p.density[i], &q.density[i], sizeof(float)) != 0;
            wrong += f.pressure && std::memcmp(&p.pressure[i], &q.pressure[i], sizeof(float)) != 0;
        }
        CHECK(wrong == 0);
        if (!f.all()) CHECK(error_of<clsph::Error>([&] { (void)clsph::read_vtu(dir.file("frame.vtu")); }).find("no array named") != std::string::npos);
    }
    CHECK(clsph::FrameFields::parse("all").all());
    const clsph::FrameFields some = clsph::FrameFields::parse("velocity,density");
    CHECK((some.velocity && some.density && !some.id && !some.type && !some.pressure));
    CHECK(error_of<clsph::Error>([] { (void)clsph::FrameFields::parse("id,spin"); }).find("--fields: unknown field \"spin\"") == 0);
    CHECK(error_of<clsph::Error>([] { (void)clsph::FrameFields::parse(""); }).find("--fields: expected") == 0);
}

TEST_CASE("VTU and CSV frames read back equal to the particles written") {
    std::mt19937 rng(scene_test::fresh_seed());
    scene_test::TempDir dir;
    for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{777},
                          std::size_t{1000 + rng() % 50000}}) {
        CAPTURE(n);
        const clsph::Particles p = random_particles(n, rng);
        clsph::write_vtu(dir.file("frame.vtu"), p);
        check_equal(p, clsph::read_vtu(dir.file("frame.vtu")));
        clsph::write_csv(dir.file("frame.csv"), p);
        check_equal(p, clsph::read_csv(dir.file("frame.csv")));
    }
    CHECK(no_temporary_files(dir));
}

TEST_CASE("a VTU frame is an unstructured grid with the arrays ParaView shows") {
    std::mt19937 rng(scene_test::fresh_seed());
    scene_test::TempDir dir;
    clsph::write_vtu(dir.file("f.vtu"), random_particles(10, rng));
    std::ifstream in(dir.file("f.vtu"), std::ios::binary);
    std::string head(2000, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head = head.substr(0, head.find("<AppendedData"));
    CHECK(head.rfind("<?xml version=\"1.0\"?>", 0) == 0);
    for (const char* s : {"type=\"UnstructuredGrid\"", "header_type=\"UInt64\"", "NumberOfPoints=\"10\"",
                          "NumberOfCells=\"10\"", "type=\"UInt32\" Name=\"id\"", "type=\"UInt8\" Name=\"type\"",
                          "type=\"Float32\" Name=\"velocity\" NumberOfComponents=\"3\"", "Name=\"density\"",
                          "Name=\"pressure\"", "type=\"Float64\" Name=\"position\" NumberOfComponents=\"3\"",
                          "Name=\"connectivity\"", "Name=\"offsets\"", "Name=\"types\""})
        CHECK_MESSAGE(head.find(s) != std::string::npos, s);
}

TEST_CASE("a CSV frame has the documented header") {
    scene_test::TempDir dir;
    clsph::Particles p;
    p.push_back(7, clsph::ParticleType::boundary, {0.1, -2.5, 1e-9}, {1.5f, 0, -0.25f}, 1000.5f, 9810.0f);
    clsph::write_csv(dir.file("f.csv"), p);
    std::ifstream in(dir.file("f.csv"));
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    CHECK(header == "id,type,x,y,z,vx,vy,vz,rho,p");
    CHECK(row == "7,1,0.1,-2.5,1e-09,1.5,0,-0.25,1000.5,9810");
}

TEST_CASE("the .pvd lists every frame with its time, valid after every frame") {
    scene_test::TempDir dir;
    const std::string pvd = dir.file("run.pvd");
    clsph::PvdWriter writer(pvd);
    CHECK(clsph::read_pvd(pvd).empty());  // valid before the first frame
    const std::vector<double> times = {0.0, 0.01, 0.02, 1.0 / 3.0, 0.1 + 0.2};
    for (std::size_t i = 0; i < times.size(); ++i) {
        const std::string file = "frames/frame_" + std::to_string(i) + (i == 2 ? "&<odd>.vtu" : ".vtu");
        writer.add(times[i], file);
        const auto entries = clsph::read_pvd(pvd);
        REQUIRE(entries.size() == i + 1);
        CHECK(entries[i].time == times[i]);  // exact: written with full precision
        CHECK(entries[i].file == file);
    }
    CHECK(writer.entries().size() == times.size());
    CHECK(no_temporary_files(dir));
}

TEST_CASE("I/O errors name the path and the OS error") {
    scene_test::TempDir dir;
    const std::string nowhere = dir.file("no/such/dir/frame.vtu");
    clsph::Particles p;
    CHECK(error_of<clsph::Error>([&] { clsph::write_vtu(nowhere, p); }) ==
          "cannot write " + nowhere + ": No such file or directory");
    CHECK(error_of<clsph::Error>([&] { clsph::write_csv(dir.file("no/f.csv"), p); }) ==
          "cannot write " + dir.file("no/f.csv") + ": No such file or directory");
    CHECK(error_of<clsph::Error>([&] { clsph::PvdWriter w(dir.file("no/run.pvd")); }) ==
          "cannot write " + dir.file("no/run.pvd") + ": No such file or directory");
    CHECK(error_of<clsph::Error>([&] { (void)clsph::read_vtu(dir.file("missing.vtu")); }) ==
          "cannot read " + dir.file("missing.vtu") + ": No such file or directory");
    CHECK(error_of<clsph::Error>([&] { (void)clsph::read_csv(dir.file("missing.csv")); }) ==
          "cannot read " + dir.file("missing.csv") + ": No such file or directory");

    // Arrays of different lengths are refused rather than read out of bounds.
    p.resize(3);
    p.density.pop_back();
    CHECK(error_of<clsph::Error>([&] { clsph::write_vtu(dir.file("f.vtu"), p); }).find("different lengths") !=
          std::string::npos);

    scene_test::write_text(dir.file("bad.csv"), "id,type,x,y,z,vx,vy,vz,rho,p\n1,0,1,2,3\n");
    CHECK(error_of<clsph::Error>([&] { (void)clsph::read_csv(dir.file("bad.csv")); }) ==
          dir.file("bad.csv") + ": line 2: expected 10 fields, got 5");
    scene_test::write_text(dir.file("bad.vtu"), "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\">");
    CHECK(error_of<clsph::Error>([&] { (void)clsph::read_vtu(dir.file("bad.vtu")); }).find(dir.file("bad.vtu") + ": ") == 0);
}
