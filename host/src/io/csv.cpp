// CSV frames: one particle per line, every number in its shortest exact decimal form, so that a
// frame read back is bit-for-bit the frame written.
#include "clsph/error.hpp"
#include "clsph/io.hpp"
#include "io/file.hpp"

#include <charconv>
#include <string_view>

namespace clsph {
namespace {

constexpr std::string_view csv_header = "id,type,x,y,z,vx,vy,vz,rho,p";

template <class T>
void append(std::string& line, T value) {
    char buf[40];
    const auto r = std::to_chars(buf, buf + sizeof buf, value);
    line.append(buf, r.ptr);
}

template <class T>
bool parse(std::string_view text, T& out) {
    const auto r = std::from_chars(text.data(), text.data() + text.size(), out);
    return r.ec == std::errc() && r.ptr == text.data() + text.size();
}

}  // namespace

void write_csv(const std::string& path, const Particles& p) { write_csv(path, p, FrameFields{}); }

void write_csv(const std::string& path, const Particles& p, const FrameFields& f) {
    io::require_consistent(p, path);
    io::OutputFile out(path);
    // The header's columns in order, those of left-out fields dropped (positions always there).
    std::string buf = std::string(f.id ? "id," : "") + (f.type ? "type," : "") + "x,y,z" + (f.velocity ? ",vx,vy,vz" : "") +
                      (f.density ? ",rho" : "") + (f.pressure ? ",p" : "");
    buf += '\n';
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (f.id) append(buf, p.id[i]), buf += ',';
        if (f.type) append(buf, static_cast<unsigned>(p.type[i])), buf += ',';
        for (int k = 0; k < 3; ++k) {
            if (k > 0) buf += ',';
            append(buf, p.position[i][k]);
        }
        if (f.velocity)
            for (float v : p.velocity[i]) buf += ',', append(buf, v);
        if (f.density) buf += ',', append(buf, p.density[i]);
        if (f.pressure) buf += ',', append(buf, p.pressure[i]);
        buf += '\n';
        if (buf.size() > (1u << 20)) {
            out.write(buf);
            buf.clear();
        }
    }
    out.write(buf);
    out.commit();
}

Particles read_csv(const std::string& path) {
    const std::string text = io::read_file(path);
    Particles p;
    std::size_t line_no = 0;
    for (std::size_t at = 0; at < text.size();) {
        std::size_t end = text.find('\n', at);
        if (end == std::string::npos) end = text.size();
        std::string_view line(text.data() + at, end - at);
        at = end + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        auto fail = [&](const std::string& what) {
            throw Error(path + ": line " + std::to_string(line_no) + ": " + what);
        };
        if (line_no == 1) {
            if (line != csv_header) fail("expected the header " + std::string(csv_header));
            continue;
        }
        if (line.empty()) continue;
        std::string_view field[10];
        std::size_t count = 0;
        for (std::size_t from = 0;; ++count) {
            const std::size_t comma = line.find(',', from);
            if (count < 10) field[count] = line.substr(from, comma == std::string_view::npos ? std::string_view::npos : comma - from);
            if (comma == std::string_view::npos) break;
            from = comma + 1;
        }
        if (++count != 10) fail("expected 10 fields, got " + std::to_string(count));
        std::uint32_t id = 0;
        unsigned type = 0;
        std::array<double, 3> x{};
        std::array<float, 3> v{};
        float rho = 0, pressure = 0;
        bool ok = parse(field[0], id) && parse(field[1], type) && type <= 1;
        for (int k = 0; k < 3; ++k) ok = ok && parse(field[2 + k], x[k]) && parse(field[5 + k], v[k]);
        ok = ok && parse(field[8], rho) && parse(field[9], pressure);
        if (!ok) fail("malformed value (expected id,type,x,y,z,vx,vy,vz,rho,p with type 0 or 1)");
        p.push_back(id, static_cast<ParticleType>(type), x, v, rho, pressure);
    }
    if (line_no == 0) throw Error(path + ": empty file (expected the header " + std::string(csv_header) + ")");
    return p;
}

}  // namespace clsph
