// Just enough XML for the files we write ourselves (VTU headers, .pvd collections): escaping
// attribute values, and reading attributes back from a tag's text.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace clsph::io {

std::string xml_escape(const std::string& text);

// The texts of all tags `<name ...>` in `xml` (from '<' to '>'), in document order.
std::vector<std::string> xml_tags(const std::string& xml, const std::string& name);

// The (unescaped) value of attribute `name` in a tag's text, if present.
std::optional<std::string> xml_attribute(const std::string& tag, const std::string& name);

}  // namespace clsph::io
