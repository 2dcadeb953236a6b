#include "scene/json_motion.hpp"

#include "scene/json_fields.hpp"
#include "scene/motion_csv.hpp"
#include "scene/wave_maker.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

namespace clsph::scene {
namespace {

std::string num(double x) {
    std::ostringstream o;
    o.precision(17);
    o << x;
    return o.str();
}

Json vec(const Vec3& v) { return Json::array({v[0], v[1], v[2]}); }

}  // namespace

bool is_csv_segment(const Json& e) {
    if (!e.is_object()) return false;
    const auto it = e.find("type");
    return it != e.end() && it->is_string() && it->get<std::string>() == "csv";
}

std::vector<MotionSegment> read_csv_segment(const Json& e, const std::string& at, const std::string& base_dir) {
    Fields g(e, at, {"type", "file", "center"});
    const std::string raw = read_string(g.require("file"), g.path_of("file"));
    if (raw.empty()) key_error(g.path_of("file"), "expected the path of a CSV file of time, x, y, z [, rx, ry, rz] rows");
    namespace fs = std::filesystem;
    fs::path p(raw);
    if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
    const MotionCsv rows = read_motion_csv(p.lexically_normal().string(), g.path_of("file"));
    const Json* c = g.find("center");
    if (!rows.angles.empty() && !c)
        key_error(g.path_of("center"), "the file's rows have angles: give the point they turn the solid about (in the scene as written)");
    if (rows.angles.empty() && c) key_error(g.path_of("center"), "the file's rows have no angles (4 columns), so nothing turns about a center");
    const Vec3 center = c ? read_vec3(*c, g.path_of("center")) : Vec3{0, 0, 0};
    return csv_motion_segments(rows, center);
}

WaveMaker read_wave_maker(const Json& v, const std::string& path, const Scene& scene, MotionSegment& segment) {
    Fields f(v, path, {"type", "height", "period", "depth", "ramp", "start", "end", "direction", "hinge", "hinge_height", "k",
                       "wavelength", "stroke"});
    WaveMaker w;
    if (!f.find("type")) key_error(f.path_of("type"), "missing required key (\"piston\" or \"flap\")");
    w.kind = f.choice("type", w.kind, {{"piston", WaveMaker::Kind::piston}, {"flap", WaveMaker::Kind::flap}});
    const bool flap = w.kind == WaveMaker::Kind::flap;
    w.height = read_number(f.require("height"), f.path_of("height"));
    w.period = read_number(f.require("period"), f.path_of("period"));
    w.depth = read_number(f.require("depth"), f.path_of("depth"));
    w.ramp = f.number("ramp", 2.0 * w.period);
    w.start = f.number("start", 0.0);
    w.end = f.number("end", scene.run.end_time);
    w.direction = f.vec3("direction", w.direction);
    for (const char* k : {"hinge", "hinge_height"})
        if (!flap && f.find(k)) key_error(f.path_of(k), "is a flap's key (this wave maker is a piston)");
    if (flap) {
        w.hinge = read_vec3(f.require("hinge"), f.path_of("hinge"));
        w.hinge_height = f.number("hinge_height", 0.0);
    }
    segment = wave_maker_segment(w, scene.physics.gravity, path);
    // A resolved scene carries the computed values; read back they must be what they were.
    for (const auto& [key, value] : {std::pair<const char*, double>{"k", w.k}, {"wavelength", w.wavelength}, {"stroke", w.stroke}})
        if (const Json* given = f.find(key)) {
            const double x = read_number(*given, f.path_of(key));
            if (!(std::abs(x - value) <= 1e-12 * std::abs(value)))
                key_error(f.path_of(key), "is computed from the height, period and depth (" + num(value) + "), not an input (got " + num(x) + ")");
        }
    return w;
}

Json wave_maker_document(const WaveMaker& w) {
    Json j;
    const bool flap = w.kind == WaveMaker::Kind::flap;
    j["type"] = flap ? "flap" : "piston";
    j["height"] = w.height;
    j["period"] = w.period;
    j["depth"] = w.depth;
    j["ramp"] = w.ramp;
    j["start"] = w.start;
    j["end"] = w.end;
    j["direction"] = vec(w.direction);
    if (flap) {
        j["hinge"] = vec(w.hinge);
        j["hinge_height"] = w.hinge_height;
    }
    j["k"] = w.k;
    j["wavelength"] = w.wavelength;
    j["stroke"] = w.stroke;
    return j;
}

}  // namespace clsph::scene
