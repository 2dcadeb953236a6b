#include "scene/motion_csv.hpp"

#include "clsph/error.hpp"
#include "scene/csv_lines.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

namespace clsph::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr const char* kColumns[7] = {"time", "x", "y", "z", "rx", "ry", "rz"};

using Mat = std::array<double, 9>;

Mat mul(const Mat& a, const Mat& b) {
    Mat c{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) c[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
    return c;
}

Mat transpose(const Mat& a) { return {a[0], a[3], a[6], a[1], a[4], a[7], a[2], a[5], a[8]}; }

// E(a) = Rz Ry Rx, a in degrees.
Mat euler(const Vec3& a) {
    const double x = a[0] * kPi / 180, y = a[1] * kPi / 180, z = a[2] * kPi / 180;
    const Mat rx{1, 0, 0, 0, std::cos(x), -std::sin(x), 0, std::sin(x), std::cos(x)};
    const Mat ry{std::cos(y), 0, std::sin(y), 0, 1, 0, -std::sin(y), 0, std::cos(y)};
    const Mat rz{std::cos(z), -std::sin(z), 0, std::sin(z), std::cos(z), 0, 0, 0, 1};
    return mul(rz, mul(ry, rx));
}

// The axis and angle (in [0, pi]) of a rotation matrix, through its quaternion (Shepperd's
// choice of the largest component, accurate near 0 and pi alike).
void axis_angle(const Mat& m, Vec3& axis, double& angle) {
    double w, x, y, z;
    const double tr = m[0] + m[4] + m[8];
    if (tr >= m[0] && tr >= m[4] && tr >= m[8]) {
        const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 + tr));
        w = 0.25 * s, x = (m[7] - m[5]) / s, y = (m[2] - m[6]) / s, z = (m[3] - m[1]) / s;
    } else if (m[0] >= m[4] && m[0] >= m[8]) {
        const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 + m[0] - m[4] - m[8]));
        w = (m[7] - m[5]) / s, x = 0.25 * s, y = (m[1] + m[3]) / s, z = (m[2] + m[6]) / s;
    } else if (m[4] >= m[8]) {
        const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 + m[4] - m[0] - m[8]));
        w = (m[2] - m[6]) / s, x = (m[1] + m[3]) / s, y = 0.25 * s, z = (m[5] + m[7]) / s;
    } else {
        const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 + m[8] - m[0] - m[4]));
        w = (m[3] - m[1]) / s, x = (m[2] + m[6]) / s, y = (m[5] + m[7]) / s, z = 0.25 * s;
    }
    if (w < 0) w = -w, x = -x, y = -y, z = -z;
    const double v = std::sqrt(x * x + y * y + z * z);
    if (v == 0) {
        axis = {0, 0, 1};
        angle = 0;
        return;
    }
    axis = {x / v, y / v, z / v};
    angle = 2.0 * std::atan2(v, w);
}

}  // namespace

MotionCsv read_motion_csv(const std::string& path, const std::string& key) {
    csv::Lines lines(path, key, "the motion file");
    auto fail = [&](const std::string& where, const std::string& what) { lines.fail(where, what); };
    MotionCsv out;
    std::size_t columns = 0, last_line = 0;
    bool seen_first = false;
    std::vector<std::string_view> fields;
    while (lines.next(fields)) {
        const std::string at = lines.at();
        if (!seen_first) {
            seen_first = true;
            if (csv::is_header(fields)) {
                if (fields.size() != 4 && fields.size() != 7)
                    fail(at, "the header has " + std::to_string(fields.size()) + " columns (expected 4: time, x, y, z, or 7: and rx, ry, rz in degrees)");
                columns = fields.size();
                continue;
            }
        }
        if (columns == 0) {
            if (fields.size() != 4 && fields.size() != 7)
                fail(at, "has " + std::to_string(fields.size()) + " columns (expected 4: time, x, y, z, or 7: and rx, ry, rz in degrees)");
            columns = fields.size();
        }
        if (fields.size() != columns)
            fail(at, "has " + std::to_string(fields.size()) + " columns, the file's rows have " + std::to_string(columns));
        double v[7] = {};
        for (std::size_t k = 0; k < columns; ++k) {
            const std::string where = at + ", column " + std::to_string(k + 1) + " (" + kColumns[k] + ")";
            if (!csv::parse_double(fields[k], v[k])) fail(where, "\"" + csv::shown(fields[k]) + "\" is not a number");
            if (!std::isfinite(v[k])) fail(where, "must be finite, got " + csv::shown(fields[k]));
            if (std::abs(v[k]) > csv::kMaxValue) fail(where, "is beyond 1e9 (" + csv::shown(fields[k]) + ")");
        }
        if (!out.time.empty() && !(v[0] > out.time.back()))
            fail(at + ", column 1 (time)", "times must increase: " + csv::num(v[0]) + " s is not after " + csv::num(out.time.back()) +
                                                " s (line " + std::to_string(last_line) + ")");
        if (out.time.size() == kMotionCsvMaxRows) fail(at, "more than " + std::to_string(kMotionCsvMaxRows) + " rows");
        out.time.push_back(v[0]);
        out.position.push_back({v[1], v[2], v[3]});
        if (columns == 7) out.angles.push_back({v[4], v[5], v[6]});
        last_line = lines.line();
    }
    if (out.time.size() < 2)
        fail("", "has " + std::to_string(out.time.size()) + " row" + (out.time.size() == 1 ? "" : "s") +
                     " of numbers; a motion needs at least 2 (time, x, y, z [, rx, ry, rz])");
    return out;
}

std::vector<MotionSegment> csv_motion_segments(const MotionCsv& rows, const Vec3& center) {
    std::vector<MotionSegment> out;
    const bool turns = !rows.angles.empty();
    const Mat first_t = turns ? transpose(euler(rows.angles[0])) : Mat{1, 0, 0, 0, 1, 0, 0, 0, 1};
    Mat q = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // the orientation at row k relative to the first row
    for (std::size_t k = 0; k + 1 < rows.time.size(); ++k) {
        MotionSegment s;
        s.type = MotionSegment::Type::linear_rotation;
        s.start = rows.time[k];
        s.end = rows.time[k + 1];
        const double dt = s.end - s.start;
        for (int a = 0; a < 3; ++a) {
            s.velocity[a] = (rows.position[k + 1][a] - rows.position[k][a]) / dt;
            s.axis_point[a] = center[a] + (rows.position[k][a] - rows.position[0][a]);
        }
        s.axis = {0, 0, 1};
        if (turns) {
            const Mat next = mul(euler(rows.angles[k + 1]), first_t);
            double angle = 0;
            axis_angle(mul(next, transpose(q)), s.axis, angle);
            s.angular_velocity = angle / dt;
            q = next;
        }
        out.push_back(s);
    }
    return out;
}

}  // namespace clsph::scene
