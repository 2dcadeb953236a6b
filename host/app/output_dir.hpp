// The run's output directory: refused when it already holds files (unless --force), created only
// once the scene has loaded and the devices are set up, so a bad input never leaves a directory.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace clsph::app {

// Throws clsph::Error when `dir` exists and is not an empty directory and `force` is off, or when
// it exists and is not a directory at all. Touches nothing.
void check_output_dir(const std::string& dir, bool force);

// Creates `dir` (and its parents); with `force`, first removes the files a run writes (frames,
// .pvd, stats, probes, run.json, the surge plot, left-over .tmp files) and leaves anything else.
void prepare_output_dir(const std::string& dir, bool force);

// The checkpoints in `dir` (checkpoint_<step>.clsph) as (step, path), oldest first.
std::vector<std::pair<std::uint64_t, std::string>> list_checkpoints(const std::string& dir);
// DIR/checkpoint_<step>.clsph, the step in at least five digits.
std::string checkpoint_path(const std::string& dir, std::uint64_t step);
// Removes all but the newest `keep` checkpoints in `dir` (--checkpoint-keep).
void remove_old_checkpoints(const std::string& dir, std::size_t keep);

}  // namespace clsph::app
