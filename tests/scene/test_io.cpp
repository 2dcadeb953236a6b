// Output files: VTU (raw and compressed, single or in pieces) and CSV frames read back equal to
// the particles written; the .pvd lists every frame with its time; errors name the path and the OS
// error.
#include "support.hpp"

#include <clsph/io.hpp>

#include <cstring>
#include <fstream>
#include <iterator>
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

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
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

// Compressed frames (issue 20, part 3): what ParaView's vtkZLibDataCompressor reads, read back by
// read_vtu equal to the raw frame, for sizes around the 64 KiB block (empty, partial, exactly full).
TEST_CASE("compressed VTU frames read back equal to the raw frame, smaller, with the zlib header") {
    std::mt19937 rng(scene_test::fresh_seed());
    scene_test::TempDir dir;
    for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{777}, std::size_t{16384}, std::size_t{65536},
                          std::size_t{1000 + rng() % 200000}}) {
        CAPTURE(n);
        const clsph::Particles p = random_particles(n, rng);
        clsph::write_vtu(dir.file("raw.vtu"), p);
        for (unsigned threads : {1u, 3u}) {
            CAPTURE(threads);
            clsph::write_vtu(dir.file("zlib.vtu"), p, clsph::FrameFields{}, clsph::VtuFormat{true, threads});
            const clsph::Particles raw = clsph::read_vtu(dir.file("raw.vtu"));
            check_equal(p, raw);
            check_equal(raw, clsph::read_vtu(dir.file("zlib.vtu")));
        }
        std::ifstream in(dir.file("zlib.vtu"), std::ios::binary);
        std::string head(2000, '\0');
        in.read(head.data(), static_cast<std::streamsize>(head.size()));
        head = head.substr(0, head.find("<AppendedData"));
        CHECK(head.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos);
        CHECK(head.find("header_type=\"UInt64\"") != std::string::npos);
        CHECK(head.find("NumberOfPoints=\"" + std::to_string(n) + "\"") != std::string::npos);
        if (n >= 777) CHECK(std::filesystem::file_size(dir.file("zlib.vtu")) < std::filesystem::file_size(dir.file("raw.vtu")));
    }
    // The raw form says nothing of a compressor; every subset of fields round-trips compressed.
    const clsph::Particles p = random_particles(5000, rng);
    clsph::write_vtu(dir.file("raw.vtu"), p);
    CHECK(read_text(dir.file("raw.vtu")).find("compressor") == std::string::npos);
    for (int mask = 0; mask < 32; mask += 5) {
        CAPTURE(mask);
        clsph::FrameFields f;
        f.id = mask & 1, f.type = mask & 2, f.velocity = mask & 4, f.density = mask & 8, f.pressure = mask & 16;
        clsph::write_vtu(dir.file("zlib.vtu"), p, f, clsph::VtuFormat{true, 2});
        clsph::FrameFields present;
        const clsph::Particles q = clsph::read_vtu(dir.file("zlib.vtu"), &present);
        CHECK((present.id == f.id && present.type == f.type && present.velocity == f.velocity && present.density == f.density &&
               present.pressure == f.pressure));
        REQUIRE(q.size() == p.size());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < p.size(); ++i)
            wrong += std::memcmp(&p.position[i], &q.position[i], sizeof p.position[i]) != 0 || (f.id && p.id[i] != q.id[i]) ||
                     (f.pressure && std::memcmp(&p.pressure[i], &q.pressure[i], sizeof(float)) != 0);
        CHECK(wrong == 0);
    }
}

TEST_CASE("a damaged compressed frame is refused naming the file and the array") {
    std::mt19937 rng(scene_test::fresh_seed());
    scene_test::TempDir dir;
    clsph::write_vtu(dir.file("zlib.vtu"), random_particles(3000, rng), clsph::FrameFields{}, clsph::VtuFormat{true, 1});
    const std::string whole = read_text(dir.file("zlib.vtu"));
    // Cut short: the last arrays lie beyond the end.
    scene_test::write_text(dir.file("short.vtu"), whole.substr(0, whole.size() * 2 / 3));
    const std::string cut = error_of<clsph::Error>([&] { (void)clsph::read_vtu(dir.file("short.vtu")); });
    CHECK(cut.find(dir.file("short.vtu") + ": array ") == 0);
    // A flipped byte inside the first array's compressed data (after its 4-block header).
    std::string flipped = whole;
    const std::size_t data = flipped.find('_', flipped.find("<AppendedData")) + 1 + 4 * 8 + 20;
    flipped[data] = static_cast<char>(flipped[data] ^ 0x5a);
    scene_test::write_text(dir.file("flipped.vtu"), flipped);
    const std::string bad = error_of<clsph::Error>([&] { (void)clsph::read_vtu(dir.file("flipped.vtu")); });
    CHECK(bad.find(dir.file("flipped.vtu") + ": array id: block 0") == 0);
    // Another compressor is named, not misread.
    std::string lz4 = whole;
    lz4.replace(lz4.find("vtkZLibDataCompressor"), 21, "vtkLZ4DataCompressor");
    scene_test::write_text(dir.file("lz4.vtu"), lz4);
    CHECK(error_of<clsph::Error>([&] { (void)clsph::read_vtu(dir.file("lz4.vtu")); }).find("vtkLZ4DataCompressor") != std::string::npos);
}

TEST_CASE("a .pvtu index reads back as its pieces concatenated, raw or compressed") {
    std::mt19937 rng(scene_test::fresh_seed());
    scene_test::TempDir dir;
    const clsph::Particles a = random_particles(1000 + rng() % 3000, rng), b = random_particles(0, rng),
                           c = random_particles(1 + rng() % 3000, rng);
    clsph::write_vtu(dir.file("f_p0.vtu"), a);
    clsph::write_vtu(dir.file("f_p1.vtu"), b, clsph::FrameFields{}, clsph::VtuFormat{true, 1});
    clsph::write_vtu(dir.file("f_p2.vtu"), c, clsph::FrameFields{}, clsph::VtuFormat{true, 2});
    clsph::write_pvtu(dir.file("f.pvtu"), {"f_p0.vtu", "f_p1.vtu", "f_p2.vtu"}, clsph::FrameFields{});
    CHECK(clsph::read_pvtu_sources(dir.file("f.pvtu")) == std::vector<std::string>{"f_p0.vtu", "f_p1.vtu", "f_p2.vtu"});
    clsph::Particles all = a;
    for (std::size_t i = 0; i < c.size(); ++i) all.push_back(c.id[i], c.type[i], c.position[i], c.velocity[i], c.density[i], c.pressure[i]);
    check_equal(all, clsph::read_vtu(dir.file("f.pvtu")));
    const std::string text = read_text(dir.file("f.pvtu"));
    for (const char* s : {"type=\"PUnstructuredGrid\"", "<PPointData", "<PDataArray type=\"UInt32\" Name=\"id\"/>",
                          "<PDataArray type=\"Float32\" Name=\"velocity\" NumberOfComponents=\"3\"/>", "<PPoints>",
                          "<PDataArray type=\"Float64\" Name=\"position\" NumberOfComponents=\"3\"/>", "<Piece Source=\"f_p2.vtu\"/>"})
        CHECK_MESSAGE(text.find(s) != std::string::npos, s);
    // Chosen fields: declared as written, reported as present.
    clsph::FrameFields f = clsph::FrameFields::parse("id,density");
    clsph::write_vtu(dir.file("g_p0.vtu"), a, f);
    clsph::write_pvtu(dir.file("g.pvtu"), {"g_p0.vtu"}, f);
    CHECK(read_text(dir.file("g.pvtu")).find("Name=\"velocity\"") == std::string::npos);
    clsph::FrameFields present;
    CHECK(clsph::read_vtu(dir.file("g.pvtu"), &present).size() == a.size());
    CHECK((present.id && present.density && !present.velocity && !present.type && !present.pressure));
    // A missing piece is named.
    clsph::write_pvtu(dir.file("h.pvtu"), {"f_p0.vtu", "gone.vtu"}, clsph::FrameFields{});
    CHECK(error_of<clsph::Error>([&] { (void)clsph::read_vtu(dir.file("h.pvtu")); }).find(dir.file("gone.vtu")) != std::string::npos);
}
