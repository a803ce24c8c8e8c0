#include "processors/plot/svg.hpp"

#include <set>

namespace gyrocal::plot {

namespace {

bool IdChar(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.' || c == ':';
}

// Every value of id='...' / id="..." in the text.
std::set<std::string> Ids(const std::string& s) {
    std::set<std::string> ids;
    for (size_t at = s.find("id="); at != std::string::npos; at = s.find("id=", at + 3)) {
        if (at > 0 && IdChar(s[at - 1])) continue;  // e.g. "uid="
        if (at + 3 >= s.size() || (s[at + 3] != '\'' && s[at + 3] != '"')) continue;
        const char q = s[at + 3];
        const size_t end = s.find(q, at + 4);
        if (end == std::string::npos) break;
        ids.insert(s.substr(at + 4, end - at - 4));
    }
    return ids;
}

// Prefixes the ids and every "#id" that names one of them.
std::string PrefixIds(const std::string& s, const std::string& prefix) {
    const std::set<std::string> ids = Ids(s);
    std::string out;
    out.reserve(s.size() + ids.size() * prefix.size() * 4);
    size_t i = 0;
    while (i < s.size()) {
        const bool id_attr = s.compare(i, 3, "id=") == 0 && (i == 0 || !IdChar(s[i - 1])) &&
                             i + 3 < s.size() && (s[i + 3] == '\'' || s[i + 3] == '"');
        if (id_attr) {
            out.append(s, i, 4);
            out += prefix;
            i += 4;
            continue;
        }
        if (s[i] == '#') {
            size_t j = i + 1;
            while (j < s.size() && IdChar(s[j])) ++j;
            if (j > i + 1 && ids.count(s.substr(i + 1, j - i - 1))) {
                out += '#';
                out += prefix;
                out.append(s, i + 1, j - i - 1);
                i = j;
                continue;
            }
        }
        out += s[i++];
    }
    return out;
}

}  // namespace

std::string XmlEscape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&#39;";
                break;
            default:
                if (static_cast<unsigned char>(c) >= 0x20 || c == '\n' || c == '\t') out += c;
        }
    }
    return out;
}

std::string InlineSvg(const std::string& svg, const std::string& name, const std::string& title) {
    const size_t root = svg.find("<svg");
    if (root == std::string::npos)
        throw SvgError("figure " + name + ": no <svg> element in gnuplot's output");
    if (svg.find("<script") != std::string::npos)
        throw SvgError("figure " + name +
                       ": gnuplot's SVG contains a script (use the plain svg terminal)");
    std::string body = PrefixIds(svg.substr(root), name + "-");
    const size_t t0 = body.find("<title>"), t1 = body.find("</title>");
    if (t0 != std::string::npos && t1 != std::string::npos && t1 > t0)
        body.replace(t0, t1 - t0 + 8, "<title>" + XmlEscape(title) + "</title>");
    body.insert(4, " data-figure=\"" + XmlEscape(name) +
                       "\" class=\"figure\" role=\"img\" aria-label=\"" + XmlEscape(title) + "\"");
    return body;
}

}  // namespace gyrocal::plot
