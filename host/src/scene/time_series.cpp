#include "scene/time_series.hpp"

#include "clsph/error.hpp"
#include "scene/csv_lines.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

namespace clsph::scene {
namespace {

std::string unit_text(const SeriesColumn& c) { return std::string(" (") + c.unit + ")"; }

}  // namespace

TimeSeries read_series_csv(const std::string& path, const std::string& key, const SeriesColumn& column) {
    csv::Lines lines(path, key, "the file");
    const std::string shape = std::string("2 columns: time, ") + column.name;
    TimeSeries out;
    bool seen_first = false;
    std::size_t last_line = 0;
    std::vector<std::string_view> fields;
    while (lines.next(fields)) {
        const std::string at = lines.at();
        if (!seen_first) {
            seen_first = true;
            if (csv::is_header(fields)) {
                if (fields.size() != 2) lines.fail(at, "the header has " + std::to_string(fields.size()) + " columns (expected " + shape + ")");
                continue;
            }
        }
        if (fields.size() != 2) lines.fail(at, "has " + std::to_string(fields.size()) + " columns (expected " + shape + ")");
        double v[2] = {};
        const char* names[2] = {"time", column.name};
        for (std::size_t k = 0; k < 2; ++k) {
            const std::string where = at + ", column " + std::to_string(k + 1) + " (" + names[k] + ")";
            if (!csv::parse_double(fields[k], v[k])) lines.fail(where, "\"" + csv::shown(fields[k]) + "\" is not a number");
            if (!std::isfinite(v[k])) lines.fail(where, "must be finite, got " + csv::shown(fields[k]));
            if (std::abs(v[k]) > csv::kMaxValue) lines.fail(where, "is beyond 1e9 (" + csv::shown(fields[k]) + ")");
        }
        if (!(v[1] >= column.min))
            lines.fail(at + ", column 2 (" + column.name + ")",
                       "must be >= " + csv::num(column.min) + unit_text(column) + ", got " + csv::shown(fields[1]));
        if (!out.time.empty() && !(v[0] > out.time.back()))
            lines.fail(at + ", column 1 (time)", "times must increase: " + csv::num(v[0]) + " s is not after " +
                                                     csv::num(out.time.back()) + " s (line " + std::to_string(last_line) + ")");
        if (out.time.size() == kSeriesMaxRows) lines.fail(at, "more than " + std::to_string(kSeriesMaxRows) + " rows");
        out.time.push_back(v[0]);
        out.value.push_back(v[1]);
        last_line = lines.line();
    }
    if (out.time.size() < 2)
        lines.fail("", "has " + std::to_string(out.time.size()) + " row" + (out.time.size() == 1 ? "" : "s") +
                           " of numbers; a series needs at least 2 (" + shape + ")");
    return out;
}

void check_series(const TimeSeries& s, const std::string& key, const SeriesColumn& column) {
    auto fail = [&](const std::string& k, const std::string& what) { throw SceneError(k + ": " + what); };
    if (s.time.size() != s.value.size()) fail(key, "the times and values differ in count");
    if (s.time.size() < 2) fail(key, "a series needs at least 2 rows [time, " + std::string(column.name) + "]");
    if (s.time.size() > kSeriesMaxRows) fail(key, "more than " + std::to_string(kSeriesMaxRows) + " rows");
    for (std::size_t i = 0; i < s.time.size(); ++i) {
        const std::string at = key + "[" + std::to_string(i) + "]";
        if (!std::isfinite(s.time[i]) || !std::isfinite(s.value[i])) fail(at, "expected finite numbers");
        if (std::abs(s.time[i]) > csv::kMaxValue || std::abs(s.value[i]) > csv::kMaxValue) fail(at, "a number is beyond 1e9");
        if (!(s.value[i] >= column.min))
            fail(at, std::string(column.name) + " must be >= " + csv::num(column.min) + unit_text(column) + ", got " + csv::num(s.value[i]));
        if (i > 0 && !(s.time[i] > s.time[i - 1]))
            fail(at, "times must increase: " + csv::num(s.time[i]) + " s is not after " + csv::num(s.time[i - 1]) + " s");
    }
}

IntegratedSeries::IntegratedSeries(const TimeSeries& s) : s_(s) {
    cumulative_.assign(s_.time.size(), 0.0);
    for (std::size_t k = 1; k < s_.time.size(); ++k)
        cumulative_[k] = cumulative_[k - 1] + 0.5 * (s_.time[k] - s_.time[k - 1]) * (s_.value[k - 1] + s_.value[k]);
    if (!s_.empty()) at_zero_ = from_first(0.0);
}

double IntegratedSeries::value(double t) const {
    if (s_.empty()) return 0.0;
    const auto& x = s_.time;
    if (t <= x.front()) return s_.value.front();
    if (t >= x.back()) return s_.value.back();
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), t) - x.begin()) - 1;
    const double f = (t - x[k]) / (x[k + 1] - x[k]);
    return s_.value[k] + f * (s_.value[k + 1] - s_.value[k]);
}

double IntegratedSeries::from_first(double t) const {
    const auto& x = s_.time;
    const auto& v = s_.value;
    if (t <= x.front()) return v.front() * (t - x.front());
    if (t >= x.back()) return cumulative_.back() + v.back() * (t - x.back());
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), t) - x.begin()) - 1;
    const double tau = t - x[k];
    return cumulative_[k] + tau * v[k] + 0.5 * tau * tau * (v[k + 1] - v[k]) / (x[k + 1] - x[k]);
}

double IntegratedSeries::integral(double t) const { return s_.empty() ? 0.0 : from_first(t) - at_zero_; }

double IntegratedSeries::max() const { return s_.empty() ? 0.0 : *std::max_element(s_.value.begin(), s_.value.end()); }

}  // namespace clsph::scene
