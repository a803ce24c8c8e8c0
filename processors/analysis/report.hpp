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

// The before/after figures of a result and its floor into anything that names them as analysis_t
// does: the ANALYSIS_<id> message (fitter) and the stored analysis row (gyrocal analyze).
template <class Out>
void CopyBeforeAfter(const SensorResult& r, Out& out) {
    out.offset_rms_v_before = r.error_before.offset_rms_v;
    out.offset_rms_v_after = r.error_after.offset_rms_v;
    out.rate_rms_dps_before = r.error_before.rate_rms_dps;
    out.rate_rms_dps_after = r.error_after.rate_rms_dps;
    out.drift_dph_before = r.error_before.drift_dph;
    out.drift_dph_after = r.error_after.drift_dph;
    out.floor_rate_rms_dps = r.floor_rate_rms_dps;
}

}  // namespace gyrocal::analysis
