#include "tests/docs/markdown.hpp"

#include <cctype>
#include <map>
#include <regex>
#include <sstream>

namespace gyrocal::docs {
namespace {

std::vector<std::string> LinesOf(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

bool IsFence(const std::string& line) { return line.rfind("```", 0) == 0; }

// `line` without a trailing "# comment" (a '#' after a blank, outside quotes), as sh reads it;
// the test appends redirections to each command, which a comment would swallow.
std::string WithoutComment(const std::string& line) {
    char quote = 0;
    for (size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quote) {
            if (c == quote) quote = 0;
        } else if (c == '\'' || c == '"') {
            quote = c;
        } else if (c == '#' && i > 0 && (line[i - 1] == ' ' || line[i - 1] == '\t')) {
            const size_t end = line.find_last_not_of(" \t", i - 1);
            return end == std::string::npos ? "" : line.substr(0, end + 1);
        }
    }
    return line;
}

}  // namespace

std::string Slug(const std::string& heading) {
    std::string out;
    for (unsigned char c : heading) {
        if (std::isalnum(c) || c == '-' || c == '_') {
            out += static_cast<char>(std::tolower(c));
        } else if (c == ' ') {
            out += '-';
        } else if (c >= 0x80) {
            out += static_cast<char>(c);  // UTF-8 letters stay, as on GitHub
        }
    }
    return out;
}

std::vector<std::string> Anchors(const std::string& markdown) {
    std::vector<std::string> out;
    std::map<std::string, int> seen;
    bool code = false;
    for (const std::string& line : LinesOf(markdown)) {
        if (IsFence(line)) code = !code;
        if (code || line.empty() || line[0] != '#') continue;
        const size_t text = line.find_first_not_of('#');
        if (text == std::string::npos || line[text] != ' ') continue;
        std::string slug = Slug(line.substr(text + 1));
        const int n = seen[slug]++;
        out.push_back(n == 0 ? slug : slug + "-" + std::to_string(n));
    }
    return out;
}

std::vector<Link> Links(const std::string& markdown) {
    static const std::regex kLink(R"(\[[^\]]*\]\(([^)\s]+)\))");
    static const std::regex kSpan("`[^`]*`");
    std::vector<Link> out;
    bool code = false;
    int n = 0;
    for (const std::string& raw : LinesOf(markdown)) {
        ++n;
        if (IsFence(raw)) code = !code;
        if (code || raw.rfind("    ", 0) == 0) continue;
        const std::string line = std::regex_replace(raw, kSpan, "");
        for (auto it = std::sregex_iterator(line.begin(), line.end(), kLink);
             it != std::sregex_iterator(); ++it)
            out.push_back({n, (*it)[1].str()});
    }
    return out;
}

std::vector<Command> ShellCommands(const std::string& markdown) {
    std::vector<Command> out;
    bool sh = false, other = false, continued = false;
    int n = 0;
    for (const std::string& line : LinesOf(markdown)) {
        ++n;
        if (IsFence(line)) {
            if (sh || other) {
                sh = other = continued = false;
            } else {
                (line == "```sh" ? sh : other) = true;
            }
            continue;
        }
        if (!sh) continue;
        const size_t start = line.find_first_not_of(' ');
        if (!continued && (start == std::string::npos || line[start] == '#')) continue;
        std::string part = start == std::string::npos ? "" : WithoutComment(line.substr(start));
        const bool more = !part.empty() && part.back() == '\\';
        if (more) part.pop_back();
        if (continued) {
            out.back().text += " " + part;
        } else {
            out.push_back({n, part});
        }
        continued = more;
    }
    return out;
}

}  // namespace gyrocal::docs
