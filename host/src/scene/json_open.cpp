#include "scene/json_open.hpp"

#include "scene/json_fields.hpp"

namespace clsph::scene {

void read_open_boundaries(const Json* inlets, const Json* outlets, Scene& s) {
    if (inlets)
        for_each_element(*inlets, "inlets", [&](const Json& e, const std::string& path) {
            Fields f(e, path, {"min", "max", "velocity", "surface"});
            Inlet in;
            in.min = read_vec3(f.require("min"), f.path_of("min"));
            in.max = read_vec3(f.require("max"), f.path_of("max"));
            in.velocity = read_vec3(f.require("velocity"), f.path_of("velocity"));
            if (const Json* z = f.find("surface"); z && !z->is_null()) in.surface = read_number(*z, f.path_of("surface"));
            s.inlets.push_back(in);
        });
    if (outlets)
        for_each_element(*outlets, "outlets", [&](const Json& e, const std::string& path) {
            Fields f(e, path, {"face"});
            const int face = f.choice("face", -1,
                                      {{"x-", 0}, {"x+", 1}, {"y-", 2}, {"y+", 3}, {"z-", 4}, {"z+", 5}});
            if (face < 0) key_error(f.path_of("face"), "required: one of \"x-\", \"x+\", \"y-\", \"y+\", \"z-\", \"z+\"");
            s.outlets.push_back(Outlet{face / 2, face % 2 == 1});
        });
}

}  // namespace clsph::scene
