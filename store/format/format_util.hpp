#pragma once
// Small text helpers shared by the store reports and exports (not part of the public API).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "processors/model/json.hpp"
#include "store/db/rows.hpp"

namespace gyrocal::format::detail {

using model::JsonNumber;  // null when not finite (JSON has no NaN)

// Column-aligned text table; cells are made printable (untrusted text).
class Table {
public:
    explicit Table(std::vector<std::string> headers);
    void Add(std::vector<std::string> row);
    std::string str() const;

private:
    std::vector<std::vector<std::string>> rows_;
};

std::string Opt(std::optional<int64_t> v);  // "-" when absent
nlohmann::json OptJson(std::optional<int64_t> v);
std::string RunLabel(const std::string& run_id);  // "(no run)" for ''
std::string Join(const std::vector<std::string>& v, const std::string& sep);
std::string Terms(const db::ModelRow& m);  // "1=2.5 dT=0.001"
// The model at temp_c [degC] by the shared evaluator, at steady state (SteadyStateInputs),
// extrapolated outside its valid range; nullopt when the model is not usable.
std::optional<double> Eval(const db::ModelRow& m, double temp_c);

}  // namespace gyrocal::format::detail
