// The options of `clsph run`, bound to a RunArgs and grouped by topic for `clsph run --help`.
// `clsph resume` parses a run's recorded command line with the same options (resume_args.hpp).
#pragma once
#include "run_args.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace clsph::app {

class RunOptions {
public:
    // Adds the options to `run`; they write into this object as `run` parses (so it stays put).
    explicit RunOptions(CLI::App& run);
    RunOptions(const RunOptions&) = delete;
    RunOptions& operator=(const RunOptions&) = delete;

    // What was parsed, --steps checked (throws clsph::Error naming it).
    RunArgs args() const;

private:
    RunArgs args_;
    // --steps is read as text and checked here: a negative or enormous count is an error, never
    // wrapped around.
    std::optional<std::string> steps_;
    std::optional<std::string> serve_;  // --serve [PORT], checked as --steps is
};

}  // namespace clsph::app
