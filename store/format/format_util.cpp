#include "store/format/format_util.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "lcmtypes/text/number.hpp"
#include "store/db/model_rows.hpp"
#include "store/format/format.hpp"

namespace gyrocal::format::detail {

Table::Table(std::vector<std::string> headers) { rows_.push_back(std::move(headers)); }

void Table::Add(std::vector<std::string> row) {
    for (auto& cell : row) cell = Printable(cell);
    rows_.push_back(std::move(row));
}

std::string Table::str() const {
    std::vector<size_t> width;
    for (const auto& r : rows_) {
        if (width.size() < r.size()) width.resize(r.size(), 0);
        for (size_t i = 0; i < r.size(); ++i) width[i] = std::max(width[i], r[i].size());
    }
    std::ostringstream out;
    for (size_t k = 0; k < rows_.size(); ++k) {
        const auto& r = rows_[k];
        std::string line;
        for (size_t i = 0; i < r.size(); ++i) {
            line += r[i];
            if (i + 1 < r.size()) line += std::string(width[i] - r[i].size() + 2, ' ');
        }
        out << line << "\n";
        if (k == 0) {
            size_t total = 0;
            for (size_t i = 0; i < width.size(); ++i) {
                total += width[i] + (i + 1 < width.size() ? 2 : 0);
            }
            out << std::string(total, '-') << "\n";
        }
    }
    return out.str();
}

std::string Opt(std::optional<int64_t> v) { return v ? std::to_string(*v) : "-"; }

nlohmann::json OptJson(std::optional<int64_t> v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

std::string RunLabel(const std::string& run_id) { return run_id.empty() ? "(no run)" : run_id; }

std::string Join(const std::vector<std::string>& v, const std::string& sep) {
    std::string out;
    for (size_t i = 0; i < v.size(); ++i) out += (i ? sep : "") + v[i];
    return out;
}

std::string Terms(const db::ModelRow& m) {
    std::vector<std::string> parts;
    for (size_t i = 0; i < m.term_names.size(); ++i) {
        parts.push_back(m.term_names[i] + "=" +
                        text::SigOrDash(i < m.coeffs.size() ? m.coeffs[i] : NAN, 6));
    }
    return Join(parts, " ");
}

std::optional<double> Eval(const db::ModelRow& m, double temp_c) {
    return db::SteadyStateValue(m, temp_c);
}

}  // namespace gyrocal::format::detail
