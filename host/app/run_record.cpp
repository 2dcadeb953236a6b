#include "run_record.hpp"

#include <clsph/error.hpp>
#include <clsph/version.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <cstdio>
#include <ctime>
#include <sstream>
#include <utility>

namespace clsph::app {

std::string utc_now() {
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return text;
}

namespace {

std::string json_string(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            case '\r': out += "\\r"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char esc[8];
                    std::snprintf(esc, sizeof esc, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
                    out += esc;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

std::string json_strings(const std::vector<std::string>& items) {
    std::string out = "[";
    for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + json_string(items[i]);
    return out + "]";
}

// JSON has no NaN or infinity: those become null.
std::string json_number(double v) {
    if (!std::isfinite(v)) return "null";
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", v);
    return text;
}

std::ofstream open_csv(const std::string& path, const char* header) {
    std::ofstream out(path);
    if (!out) throw Error("cannot create " + path);
    out << header << '\n';
    return out;
}

// A resume: the CSV at `path` rewritten with its header and the rows whose first field passes
// `keep` (rows are in order: the first that fails ends it), then opened for appending.
std::ofstream reopen_csv(const std::string& path, const char* header, const std::function<bool(const std::string&)>& keep) {
    std::vector<std::string> rows;
    {
        std::ifstream in(path);
        std::string line;
        bool first = true;
        while (std::getline(in, line)) {
            if (first) {
                first = false;
                continue;
            }
            const std::string field = line.substr(0, line.find(','));
            if (line.find(',') == std::string::npos || !keep(field)) break;
            rows.push_back(line);
        }
    }
    {
        std::ofstream out(path, std::ios::trunc);
        out << header << '\n';
        for (const auto& r : rows) out << r << '\n';
        if (!out) throw Error("cannot rewrite " + path);
    }
    std::ofstream out(path, std::ios::app);
    if (!out) throw Error("cannot append to " + path);
    return out;
}

}  // namespace

RunRecord::RunRecord(std::string dir, RunIdentity identity, const std::vector<Probe>& probes, const ResumePoint* resume,
                     bool writes)
    : dir_(std::move(dir)), identity_(std::move(identity)), started_(utc_now()), last_flush_(std::chrono::steady_clock::now()),
      writes_(writes) {
    if (!writes_) return;
    if (!identity_.start_time.empty()) started_ = identity_.start_time;
    const char* stats_header = "step,time,dt,particles,fluid,removed,kinetic_energy,max_speed,created";
    if (resume) {
        resumed_ = true;
        resume_time_ = resume->time;
        const auto step = resume->step;
        const double t = resume->time, eps = 1e-8 * std::max(1.0, std::abs(resume->time));  // the rows hold 9 digits
        stats_ = reopen_csv(dir_ + "/stats.csv", stats_header,
                            [step](const std::string& f) { return std::stoull(f) <= step; });
        for (const auto& p : probes) {
            const std::string path = dir_ + "/probe_" + safe_name(p.name) + ".csv";
            probe_files_.emplace_back(p.name, std::make_unique<std::ofstream>(reopen_csv(
                                                  path, "time,value", [t, eps](const std::string& f) { return std::stod(f) <= t + eps; })));
        }
    } else {
        stats_ = open_csv(dir_ + "/stats.csv", stats_header);
        for (const auto& p : probes) {
            const std::string path = dir_ + "/probe_" + safe_name(p.name) + ".csv";
            probe_files_.emplace_back(p.name, std::make_unique<std::ofstream>(open_csv(path, "time,value")));
        }
    }
    write_json(Ending{"running"});
}

void RunRecord::step(const StepInfo& s) {
    if (!writes_) return;
    char row[256];
    std::snprintf(row, sizeof row, "%llu,%.9g,%.6g,%zu,%zu,%zu,%.6g,%.6g,%zu\n", static_cast<unsigned long long>(s.step),
                  s.time, s.dt, s.particles, s.fluid, s.removed, s.kinetic_energy, s.max_speed, s.created);
    stats_ << row;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_flush_ > std::chrono::seconds(1)) {
        last_flush_ = now;
        stats_.flush();
        for (auto& entry : probe_files_) entry.second->flush();
    }
    if (!stats_) throw Error("cannot write " + dir_ + "/stats.csv");
}

void RunRecord::probes(const std::vector<ProbeSample>& samples) {
    if (!writes_) return;
    for (const auto& s : samples) {
        for (auto& [name, file] : probe_files_) {
            if (name != s.name) continue;
            char row[64];
            std::snprintf(row, sizeof row, "%.9g,%.9g\n", s.time, s.value);  // NaN prints as nan
            *file << row;
            if (!*file) throw Error("cannot write " + dir_ + "/probe_" + safe_name(name) + ".csv");
        }
    }
}

void RunRecord::bodies(const std::vector<BodySample>& samples) {
    if (!writes_ || samples.empty()) return;
    static const char* header =
        "time,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,fx,fy,fz,tx,ty,tz";
    if (body_files_.empty()) {
        const double t = resume_time_, eps = 1e-8 * std::max(1.0, std::abs(t));
        for (const auto& b : samples) {
            const std::string path = dir_ + "/body_" + safe_name(b.name) + ".csv";
            body_files_.push_back(std::make_unique<std::ofstream>(
                resumed_ ? reopen_csv(path, header, [t, eps](const std::string& f) { return std::stod(f) <= t + eps; })
                         : open_csv(path, header)));
        }
    }
    for (std::size_t i = 0; i < samples.size() && i < body_files_.size(); ++i) {
        const auto& b = samples[i];
        std::ostringstream row;
        row.precision(9);
        row << b.time;
        for (double x : b.position) row << ',' << x;
        for (double x : b.quaternion) row << ',' << x;
        for (const auto* a : {&b.velocity, &b.angular_velocity, &b.force, &b.torque})
            for (double x : *a) row << ',' << x;
        *body_files_[i] << row.str() << '\n';
        if (!*body_files_[i]) throw Error("cannot write " + dir_ + "/body_" + safe_name(b.name) + ".csv");
    }
    last_bodies_ = samples;
}

void RunRecord::flush() {
    if (!writes_) return;
    last_flush_ = std::chrono::steady_clock::now();
    stats_.flush();
    for (auto& f : body_files_) f->flush();
    if (!stats_) throw Error("cannot write " + dir_ + "/stats.csv");
    for (auto& [name, file] : probe_files_) {
        file->flush();
        if (!*file) throw Error("cannot write " + dir_ + "/probe_" + safe_name(name) + ".csv");
    }
}

void RunRecord::finish(const std::string& status, const StepInfo& last, const std::string& message, int exit_status,
                       const std::string& signal) {
    if (!writes_) return;
    stats_.flush();
    for (auto& entry : probe_files_) entry.second->flush();
    for (auto& f : body_files_) f->flush();
    write_json(Ending{status, &last, message, exit_status, signal});
}

std::string RunRecord::abort_text(const StepInfo& last) const {
    return json_text(Ending{"aborted", &last,
                            "a second Ctrl-C or SIGTERM ended the run at once; the frames listed in the .pvd are "
                            "complete, and so are stats.csv and the probe files up to the last of them"});
}

std::string RunRecord::safe_name(const std::string& name) {
    std::string out;
    for (const char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                        c == '_' || c == '.';
        out += ok ? c : '_';
    }
    return out.empty() ? "unnamed" : out;
}

std::string RunRecord::json_text(const Ending& e) const {
    const StepInfo* last = e.last;
    std::ostringstream j;
    j << "{\n"
      << "  \"clsph_version\": " << json_string(version()) << ",\n"
      << "  \"command_line\": " << json_strings(identity_.command_line) << ",\n"
      << "  \"scene_file\": " << json_string(identity_.scene_file) << ",\n"
      << "  \"overrides\": " << json_strings(identity_.overrides) << ",\n"
      << "  \"devices\": " << json_strings(identity_.devices) << ",\n"
      << "  \"interaction\": " << json_strings(identity_.interactions) << ",\n";
    if (!identity_.cell_order.empty()) j << "  \"cell_order\": " << json_string(identity_.cell_order) << ",\n";
    j << "  \"start_time\": " << json_string(started_) << ",\n";
    if (!identity_.resumes.empty()) {
        j << "  \"resumes\": [";
        for (std::size_t i = 0; i < identity_.resumes.size(); ++i) j << (i ? ", " : "") << identity_.resumes[i];
        j << "],\n";
    }
    j << "  \"status\": " << json_string(e.status) << ",\n";
    if (e.exit_status >= 0) j << "  \"exit_status\": " << e.exit_status << ",\n";
    if (!e.signal.empty()) j << "  \"signal\": " << json_string(e.signal) << ",\n";
    if (!e.message.empty()) j << "  \"message\": " << json_string(e.message) << ",\n";
    if (last) {
        j << "  \"finish_time\": " << json_string(utc_now()) << ",\n"
          << "  \"steps\": " << last->step << ",\n"
          << "  \"simulated_time\": " << json_number(last->time) << ",\n"
          << "  \"wall_seconds\": " << json_number(last->wall_seconds) << ",\n"
          << "  \"particles\": " << last->particles << ",\n"
          << "  \"removed\": " << last->removed << ",\n";
        if (table_builds_ > 0) j << "  \"table_builds\": " << table_builds_ << ",\n";
        j << "  \"steps_ahead\": " << steps_ahead_ << ",\n"
          << "  \"steps_thrown\": " << steps_thrown_ << ",\n";
    }
    if (!last_bodies_.empty()) {  // floating bodies: their state at the last row written
        j << "  \"bodies\": [";
        auto arr = [&](const auto& a) {
            std::string s = "[";
            for (std::size_t k = 0; k < a.size(); ++k) s += (k ? ", " : "") + json_number(a[k]);
            return s + "]";
        };
        for (std::size_t i = 0; i < last_bodies_.size(); ++i) {
            const auto& b = last_bodies_[i];
            j << (i ? ",\n    " : "\n    ") << "{\"name\": " << json_string(b.name) << ", \"time\": " << json_number(b.time)
              << ", \"mass\": " << json_number(b.mass) << ", \"position\": " << arr(b.position)
              << ", \"quaternion\": " << arr(b.quaternion) << ", \"velocity\": " << arr(b.velocity)
              << ", \"angular_velocity\": " << arr(b.angular_velocity) << ", \"force\": " << arr(b.force)
              << ", \"torque\": " << arr(b.torque) << "}";
        }
        j << "\n  ],\n";
    }
    // The scene text is already JSON; indent it one level so the file reads as a whole.
    std::string scene = identity_.scene_json;
    while (!scene.empty() && (scene.back() == '\n' || scene.back() == ' ')) scene.pop_back();
    std::string indented;
    for (const char c : scene) indented += c == '\n' ? std::string("\n  ") : std::string(1, c);
    j << "  \"scene\": " << indented << "\n}\n";
    return j.str();
}

void RunRecord::write_json(const Ending& e) const {
    const std::string text = json_text(e);

    // Whole or not at all: a reader never sees half a run.json.
    const std::string path = dir_ + "/run.json", tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << text;
        out.close();
        if (!out) throw Error("cannot write " + tmp);
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) throw Error("cannot rename " + tmp + " to " + path);
}

}  // namespace clsph::app
