// The scene keys of motions read from elsewhere (docs/scenes.md, motion): a segment {"type":
// "csv", "file", "center"} (scene/motion_csv.hpp) and a motion {"wave_maker": {...}}
// (scene/wave_maker.hpp), and the wave maker written back into a resolved scene.
#pragma once
#include "clsph/scene.hpp"
#include "scene/json_parse.hpp"

#include <string>
#include <vector>

namespace clsph::scene {

// True for a segment object whose "type" is "csv".
bool is_csv_segment(const Json& e);
// The linear_rotation segments of a {"type": "csv"} segment at `at`; `file` relative to base_dir.
std::vector<MotionSegment> read_csv_segment(const Json& e, const std::string& at, const std::string& base_dir);
// A wave maker at `path` ("...motion.wave_maker") with its computed k, wavelength and stroke,
// and its one segment in `segment`; `end` defaults to the run's end (scene.run.end_time).
WaveMaker read_wave_maker(const Json& v, const std::string& path, const Scene& scene, MotionSegment& segment);
// Its keys as read, defaults filled, and the computed k, wavelength and stroke.
Json wave_maker_document(const WaveMaker& w);

}  // namespace clsph::scene
