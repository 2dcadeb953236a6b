#include "clsph/interaction.hpp"

#include "clsph/error.hpp"

namespace clsph {

namespace {
struct Named {
    Interaction form;
    const char* name;
};
constexpr Named kNames[] = {{Interaction::automatic, "auto"},
                            {Interaction::fine, "fine"},
                            {Interaction::lanes, "lanes"},
                            {Interaction::coarse, "coarse"},
                            {Interaction::clusters, "clusters"}};
}  // namespace

const char* interaction_name(Interaction form) {
    for (const auto& n : kNames)
        if (n.form == form) return n.name;
    return "?";
}

Interaction interaction_from_name(const std::string& name) {
    std::string list;
    for (const auto& n : kNames) {
        if (name == n.name) return n.form;
        list += list.empty() ? n.name : std::string(", ") + n.name;
    }
    throw Error("unknown interaction form '" + name + "' (choose one of " + list + ")");
}

std::vector<Interaction> interaction_forms() {
    return {Interaction::fine, Interaction::lanes, Interaction::coarse, Interaction::clusters};
}

}  // namespace clsph
