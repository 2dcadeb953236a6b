// clsph resume DIR: the command line recorded in DIR/run.json, with --out DIR and the resume's own
// --until, --devices and --steps in place of the original's, parsed as `clsph run` parses it.
#pragma once
#include "run_args.hpp"

#include <optional>
#include <string>
#include <vector>

namespace clsph::app {

// `own_argv`: the resume's own command line (run.json's resumes). Throws clsph::Error when DIR is
// not the output directory of a clsph run or its command line does not parse.
RunArgs resume_args(const std::string& dir, const std::optional<double>& until, const std::string& devices,
                    const std::optional<std::string>& steps, const std::vector<std::string>& own_argv);

}  // namespace clsph::app
