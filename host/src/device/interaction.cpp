#include "clsph/interaction.hpp"

#include "clsph/error.hpp"

#include <utility>

namespace clsph {

namespace {
// A value's name in a table of (value, name) pairs, and the inverse, which lists the names.
template <typename T, std::size_t N>
const char* name_in(const std::pair<T, const char*> (&table)[N], T value) {
    for (const auto& [v, name] : table)
        if (v == value) return name;
    return "?";
}

template <typename T, std::size_t N>
T value_in(const std::pair<T, const char*> (&table)[N], const std::string& name, const char* what) {
    std::string list;
    for (const auto& [v, n] : table) {
        if (name == n) return v;
        list += list.empty() ? n : std::string(", ") + n;
    }
    throw Error(std::string("unknown ") + what + " '" + name + "' (choose one of " + list + ")");
}

constexpr std::pair<Interaction, const char*> kForms[] = {{Interaction::automatic, "auto"},
                                                          {Interaction::fine, "fine"},
                                                          {Interaction::lanes, "lanes"},
                                                          {Interaction::coarse, "coarse"},
                                                          {Interaction::clusters, "clusters"}};
constexpr std::pair<CellOrder, const char*> kOrders[] = {
    {CellOrder::automatic, "auto"}, {CellOrder::arrival, "arrival"}, {CellOrder::morton, "morton"}};
}  // namespace

const char* interaction_name(Interaction form) { return name_in(kForms, form); }

Interaction interaction_from_name(const std::string& name) { return value_in(kForms, name, "interaction form"); }

std::vector<Interaction> interaction_forms() {
    return {Interaction::fine, Interaction::lanes, Interaction::coarse, Interaction::clusters};
}

const char* cell_order_name(CellOrder order) { return name_in(kOrders, order); }

CellOrder cell_order_from_name(const std::string& name) { return value_in(kOrders, name, "cell order"); }

}  // namespace clsph
