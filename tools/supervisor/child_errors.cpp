#include "tools/supervisor/child_errors.hpp"

#include <sstream>

#include "lcmtypes/process/process_main.hpp"

namespace gyrocal::supervisor {

std::vector<std::string> ErrorLinesOf(const std::string& log_text, const std::string& process,
                                      size_t max_lines) {
    std::vector<std::string> errors;
    std::string last;
    std::istringstream in(log_text);
    const size_t prefix = process::ErrorLine(process, "").size();
    for (std::string line; std::getline(in, line);) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.find_first_not_of(" \t") == std::string::npos) continue;
        last = line;
        if (process::IsErrorLineOf(process, line)) errors.push_back(line.substr(prefix));
    }
    if (errors.empty()) {
        if (last.empty()) return {};
        return {"last line of its log: " + last};
    }
    if (errors.size() > max_lines) errors.erase(errors.begin(), errors.end() - max_lines);
    return errors;
}

std::string WithCause(const std::string& what, const std::vector<std::string>& lines) {
    std::string out = what;
    for (size_t i = 0; i < lines.size(); ++i) out += (i == 0 ? "; it said: " : " | ") + lines[i];
    return out;
}

}  // namespace gyrocal::supervisor
