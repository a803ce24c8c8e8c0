#include "producers/csv/fields.hpp"

#include <charconv>
#include <cmath>

namespace gyrocal::csv {
namespace {
std::string_view Trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
        s.remove_suffix(1);
    return s;
}
}  // namespace

std::vector<std::string> SplitFields(std::string_view line) {
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    std::vector<std::string> out;
    size_t start = 0;
    while (true) {
        const size_t comma = line.find(',', start);
        std::string_view f = Trim(line.substr(
            start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
        if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
        out.emplace_back(f);
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    return out;
}

bool IsBlankOrComment(std::string_view line) {
    line = Trim(line);
    return line.empty() || line.front() == '#';
}

Number ParseNumber(std::string_view field) {
    Number n;
    if (field.empty()) return n;
    std::string_view s = field;
    if (s.front() == '+') s.remove_prefix(1);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || s.empty()) {
        n.status = NumberStatus::kNotANumber;
        return n;
    }
    n.status = std::isfinite(v) ? NumberStatus::kOk : NumberStatus::kNotFinite;
    n.value = v;
    return n;
}

}  // namespace gyrocal::csv
