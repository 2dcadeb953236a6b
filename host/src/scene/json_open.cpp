#include "scene/json_open.hpp"

#include "scene/json_fields.hpp"
#include "scene/time_series.hpp"

#include <filesystem>

namespace clsph::scene {
namespace {

Json vec(const Vec3& v) { return Json::array({v[0], v[1], v[2]}); }

// [[a, b], ...]: pairs of numbers (`what` names them in the message: "time, speed").
std::vector<std::array<double, 2>> read_pairs(const Json& v, const std::string& path, const std::string& what) {
    std::vector<std::array<double, 2>> out;
    for_each_element(v, path, [&](const Json& e, const std::string& at) {
        if (!e.is_array() || e.size() != 2) key_error(at, "expected 2 numbers [" + what + "]");
        out.push_back({read_number(e[0], at + "[0]"), read_number(e[1], at + "[1]")});
    });
    return out;
}

TimeSeries series_of(const std::vector<std::array<double, 2>>& rows) {
    TimeSeries s;
    for (const auto& r : rows) s.time.push_back(r[0]), s.value.push_back(r[1]);
    return s;
}

Json rows_of(const TimeSeries& s) {
    Json rows = Json::array();
    for (std::size_t i = 0; i < s.time.size(); ++i) rows.push_back(Json::array({s.time[i], s.value[i]}));
    return rows;
}

// `csv_key` (a file of time, value rows) or `rows_key` (the rows inline), not both; empty: neither.
TimeSeries read_series(Fields& f, const char* csv_key, const char* rows_key, const SeriesColumn& column,
                       const std::string& base_dir) {
    const Json* file = f.find(csv_key);
    const Json* rows = f.find(rows_key);
    if (file && rows) key_error(f.path_of(rows_key), std::string("give ") + csv_key + " or " + rows_key + ", not both");
    if (rows) return series_of(read_pairs(*rows, f.path_of(rows_key), std::string("time, ") + column.name));
    if (!file) return {};
    const std::string raw = read_string(*file, f.path_of(csv_key));
    if (raw.empty()) key_error(f.path_of(csv_key), std::string("expected the path of a CSV file of time, ") + column.name + " rows");
    namespace fs = std::filesystem;
    fs::path p(raw);
    if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
    return read_series_csv(p.lexically_normal().string(), f.path_of(csv_key), column);
}

int read_axis(const Json& v, const std::string& path) {
    const std::string a = read_string(v, path);
    if (a == "x") return 0;
    if (a == "y") return 1;
    if (a == "z") return 2;
    key_error(path, "unknown value \"" + a + "\" (expected one of \"x\", \"y\", \"z\")");
}

Inlet read_inlet(const Json& e, const std::string& path, const std::string& base_dir) {
    Fields f(e, path, {"min", "max", "velocity", "surface", "speed_csv", "speed_series", "profile"});
    Inlet in;
    in.min = read_vec3(f.require("min"), f.path_of("min"));
    in.max = read_vec3(f.require("max"), f.path_of("max"));
    in.velocity = read_vec3(f.require("velocity"), f.path_of("velocity"));
    if (const Json* z = f.find("surface"); z && !z->is_null()) in.surface = read_number(*z, f.path_of("surface"));
    in.speed = read_series(f, "speed_csv", "speed_series", SeriesColumn{"speed", "m/s", 0.0}, base_dir);
    if (const Json* p = f.find("profile"); p && !p->is_null()) {
        Fields g(*p, f.path_of("profile"), {"axis", "points"});
        in.profile.axis = read_axis(g.require("axis"), g.path_of("axis"));
        in.profile.points = read_pairs(g.require("points"), g.path_of("points"), "coordinate, factor");
    }
    return in;
}

Outlet read_outlet(const Json& e, const std::string& path, const std::string& base_dir) {
    Fields f(e, path, {"face", "min", "max", "pressure", "level", "level_csv", "level_series"});
    const int face = f.choice("face", -1, {{"x-", 0}, {"x+", 1}, {"y-", 2}, {"y+", 3}, {"z-", 4}, {"z+", 5}});
    if (face < 0) key_error(f.path_of("face"), "required: one of \"x-\", \"x+\", \"y-\", \"y+\", \"z-\", \"z+\"");
    Outlet o;
    o.axis = face / 2;
    o.upper = face % 2 == 1;
    const Json* lo = f.find("min");
    const Json* hi = f.find("max");
    if (lo || hi) {  // a zone: both corners
        o.zone = true;
        o.min = read_vec3(f.require("min"), f.path_of("min"));
        o.max = read_vec3(f.require("max"), f.path_of("max"));
    }
    const char* first = nullptr;  // what the zone holds: one of pressure, level, a level in time
    for (const char* k : {"pressure", "level", "level_csv", "level_series"}) {
        if (!f.find(k)) continue;
        if (!o.zone) key_error(f.path_of(k), "needs a zone (min and max): a face of the domain holds no pressure or level");
        if (first && !(std::string(first) == "level_csv" && std::string(k) == "level_series"))
            key_error(f.path_of(k), std::string("give one of pressure, level, level_csv and level_series; ") + first + " is given");
        first = k;
    }
    if (const Json* p = f.find("pressure")) o.pressure = read_number(*p, f.path_of("pressure"));
    if (const Json* l = f.find("level")) o.level = read_number(*l, f.path_of("level"));
    o.level_series = read_series(f, "level_csv", "level_series", SeriesColumn{"level", "m"}, base_dir);
    return o;
}

}  // namespace

void read_open_boundaries(const Json* inlets, const Json* outlets, const std::string& base_dir, Scene& s) {
    if (inlets)
        for_each_element(*inlets, "inlets", [&](const Json& e, const std::string& path) { s.inlets.push_back(read_inlet(e, path, base_dir)); });
    if (outlets)
        for_each_element(*outlets, "outlets", [&](const Json& e, const std::string& path) { s.outlets.push_back(read_outlet(e, path, base_dir)); });
}

void write_open_boundaries(const Scene& s, Json& doc) {
    // Only where there are some: a closed scene's document (and hash) as before; likewise the new
    // keys only where given, so an inlet of constant speed writes what it always did.
    if (!s.inlets.empty()) {
        Json inlets = Json::array();
        for (const auto& in : s.inlets) {
            Json j;
            j["min"] = vec(in.min);
            j["max"] = vec(in.max);
            j["velocity"] = vec(in.velocity);
            j["surface"] = in.surface ? Json(*in.surface) : Json(nullptr);
            if (!in.speed.empty()) j["speed_series"] = rows_of(in.speed);
            if (in.profile.axis >= 0) {
                Json points = Json::array();
                for (const auto& p : in.profile.points) points.push_back(Json::array({p[0], p[1]}));
                j["profile"] = Json{{"axis", std::string(1, "xyz"[in.profile.axis])}, {"points", points}};
            }
            inlets.push_back(j);
        }
        doc["inlets"] = inlets;
    }
    if (!s.outlets.empty()) {
        Json outlets = Json::array();
        for (const auto& o : s.outlets) {
            Json j{{"face", std::string(1, "xyz"[o.axis]) + (o.upper ? "+" : "-")}};
            if (o.zone) {
                j["min"] = vec(o.min);
                j["max"] = vec(o.max);
                if (o.pressure) j["pressure"] = *o.pressure;
                if (o.level) j["level"] = *o.level;
                if (!o.level_series.empty()) j["level_series"] = rows_of(o.level_series);
            }
            outlets.push_back(j);
        }
        doc["outlets"] = outlets;
    }
}

}  // namespace clsph::scene
