#pragma once
// The analysis result as JSON (`gyrocal analyze --json`: sensors[] with sensor_id, verdict,
// candidates[] {effect, statistic, decision}, added[] {effect, term, coefficient, stderr, unit},
// error_before / error_after {offset_rms_v, rate_rms_dps, drift_dph}, floor_rate_rms_dps; plus
// extra fields) and as a human table. Non-finite numbers are written as null.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"

namespace gyrocal::analysis {

nlohmann::json ToJson(const SensorResult& result);
// {"sensors": [...]}.
nlohmann::json ToJson(const std::vector<SensorResult>& results);

std::string FormatReport(const SensorResult& result);

}  // namespace gyrocal::analysis
