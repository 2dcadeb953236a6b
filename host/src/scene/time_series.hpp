// Quantities in time given by rows (clsph/scene.hpp, TimeSeries): an inlet's speed, an outlet's
// water level. Read from a CSV file of `time, value` rows (scene/csv_lines.hpp's care), checked
// when given inline, and evaluated: linear between rows, the end rows' values beyond them, and the
// exact integral of that from t = 0 (an inlet's travelled distance). Pure host code.
#pragma once
#include "clsph/scene.hpp"

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace clsph::scene {

// The value column of a series: its name and unit in messages, and the least value allowed.
struct SeriesColumn {
    const char* name;
    const char* unit;
    double min = -std::numeric_limits<double>::infinity();
};

// The most rows a series may have (as a motion file).
constexpr std::size_t kSeriesMaxRows = 100000;

// Reads `path`: 2 comma-separated numbers a row (time, value); blank lines and lines starting with
// '#' skipped, a first line starting with a letter a header. At least 2 rows, times strictly
// increasing, every value finite, |value| <= 1e9 and >= column.min. Errors are SceneError
// "key: path, line L, column C (name): what".
TimeSeries read_series_csv(const std::string& path, const std::string& key, const SeriesColumn& column);

// The same checks for rows given in the scene: SceneError naming "key[i]".
void check_series(const TimeSeries& s, const std::string& key, const SeriesColumn& column);

class IntegratedSeries {
public:
    IntegratedSeries() = default;
    explicit IntegratedSeries(const TimeSeries& s);
    double value(double t) const;     // linear between rows, held beyond them
    double integral(double t) const;  // of value() from 0 to t (exact: trapezoids and one partial piece)
    double max() const;               // the largest value

private:
    double from_first(double t) const;  // the integral from the first row's time
    TimeSeries s_;
    std::vector<double> cumulative_;  // the integral from the first row to row k
    double at_zero_ = 0;              // from_first(0)
};

}  // namespace clsph::scene
