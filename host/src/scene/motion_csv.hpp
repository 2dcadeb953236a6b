// A solid's motion from a CSV file (docs/scenes.md, a segment {"type": "csv"}): rows of time, x,
// y, z and optionally three angles rx, ry, rz in degrees. The solid moves by the rows' change
// since the first row: at a row's time a particle resting at x0 is at
//     center + (p - p_first) + E(a) E(a_first)^T (x0 - center),
// E(a) = Rz(rz) Ry(ry) Rx(rx) (about the fixed x, then y, then z axis, as a mesh's rotate), where
// `center` is the point (in the scene as written) the angles turn about. Between two rows the
// position is interpolated linearly in time and the orientation turns at a constant rate about
// the fixed axis that takes one row's orientation to the next (the shortest such turn: slerp),
// which is the linear interpolation of the angle when one angle changes; so each interval is one
// linear_rotation segment, and the velocity is that interpolation's. Before the first row and
// after the last the solid rests. Pure host code.
#pragma once
#include "clsph/scene.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace clsph::scene {

struct MotionCsv {
    std::vector<double> time;
    std::vector<Vec3> position;
    std::vector<Vec3> angles;  // degrees; empty when the file has 4 columns
};

// The most rows a motion file may have (each becomes a segment of the device's table).
constexpr std::size_t kMotionCsvMaxRows = 100000;

// Reads `path`: comma-separated numbers, 4 or 7 a row (every row alike); blank lines and lines
// starting with '#' are skipped; a first line whose first field starts with a letter is a
// header. At least 2 rows, times strictly increasing, every value finite. Errors are SceneError
// "key: path, line L, column C (name): what".
MotionCsv read_motion_csv(const std::string& path, const std::string& key);

// The linear_rotation segments of the rows (one per interval), turning about `center`.
std::vector<MotionSegment> csv_motion_segments(const MotionCsv& rows, const Vec3& center);

}  // namespace clsph::scene
