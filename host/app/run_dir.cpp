#include "run_dir.hpp"

#include <clsph/error.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace clsph::app {

Scene scene_of_run(const std::string& dir, const std::string& command) {
    const std::string record = dir + "/run.json";
    std::ifstream in(record);
    if (!in) throw Error(command + ": cannot read " + record + " (is " + dir + " the output directory of clsph run?)");
    nlohmann::json run;
    try {
        in >> run;
    } catch (const std::exception& e) {
        throw Error(record + ": not valid JSON (" + e.what() + ")");
    }
    if (!run.contains("scene") || !run["scene"].is_object()) throw Error(record + ": has no \"scene\" object");
    return Scene::from_json_text(run["scene"].dump(), record + ": scene");
}

std::string frames_pvd(const std::string& dir) {
    namespace fs = std::filesystem;
    std::string pvd;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".pvd" && e.path().filename() != "surface.pvd") pvd = e.path().string();
    return pvd;
}

}  // namespace clsph::app
