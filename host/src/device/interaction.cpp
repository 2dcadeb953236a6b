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

namespace {
struct NamedOrder {
    CellOrder order;
    const char* name;
};
constexpr NamedOrder kOrders[] = {{CellOrder::automatic, "auto"}, {CellOrder::arrival, "arrival"}, {CellOrder::morton, "morton"}};
}  // namespace

const char* cell_order_name(CellOrder order) {
    for (const auto& n : kOrders)
        if (n.order == order) return n.name;
    return "?";
}

CellOrder cell_order_from_name(const std::string& name) {
    std::string list;
    for (const auto& n : kOrders) {
        if (name == n.name) return n.order;
        list += list.empty() ? n.name : std::string(", ") + n.name;
    }
    throw Error("unknown cell order '" + name + "' (choose one of " + list + ")");
}

}  // namespace clsph
