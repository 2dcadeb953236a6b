#include "io/xml.hpp"

#include <cctype>

namespace clsph::io {
namespace {

std::string xml_unescape(const std::string& text) {
    static const std::pair<const char*, char> entities[] = {
        {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
    std::string out;
    for (std::size_t i = 0; i < text.size();) {
        bool replaced = false;
        if (text[i] == '&')
            for (const auto& [entity, c] : entities)
                if (text.compare(i, std::char_traits<char>::length(entity), entity) == 0) {
                    out += c;
                    i += std::char_traits<char>::length(entity);
                    replaced = true;
                    break;
                }
        if (!replaced) out += text[i++];
    }
    return out;
}

}  // namespace

std::string xml_escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default: out += c;
        }
    }
    return out;
}

std::vector<std::string> xml_tags(const std::string& xml, const std::string& name) {
    std::vector<std::string> tags;
    const std::string open = "<" + name;
    for (std::size_t at = xml.find(open); at != std::string::npos; at = xml.find(open, at + 1)) {
        const std::size_t after = at + open.size();
        // "<DataArray" must not match "<DataArrayX": the name ends at a space, '/' or '>'.
        if (after < xml.size() && !(std::isspace(static_cast<unsigned char>(xml[after])) || xml[after] == '/' || xml[after] == '>'))
            continue;
        const std::size_t end = xml.find('>', after);
        if (end == std::string::npos) break;
        tags.push_back(xml.substr(at, end - at + 1));
    }
    return tags;
}

std::optional<std::string> xml_attribute(const std::string& tag, const std::string& name) {
    for (std::size_t at = tag.find(name + "=\""); at != std::string::npos; at = tag.find(name + "=\"", at + 1)) {
        // A whole attribute name: preceded by white space.
        if (at == 0 || !std::isspace(static_cast<unsigned char>(tag[at - 1]))) continue;
        const std::size_t begin = at + name.size() + 2;
        const std::size_t end = tag.find('"', begin);
        if (end == std::string::npos) return std::nullopt;
        return xml_unescape(tag.substr(begin, end - begin));
    }
    return std::nullopt;
}

}  // namespace clsph::io
