#include "balance/options.hpp"

namespace clsph::balance {

std::string_view to_string(Mode mode) {
  switch (mode) {
    case Mode::dynamic: return "dynamic";
    case Mode::static_: return "static";
    case Mode::off: return "off";
  }
  return "unknown";
}

std::optional<Mode> mode_from_string(std::string_view text) {
  if (text == "dynamic") return Mode::dynamic;
  if (text == "static") return Mode::static_;
  if (text == "off") return Mode::off;
  return std::nullopt;
}

}  // namespace clsph::balance
