#include "processors/analysis/validate.hpp"

#include <algorithm>
#include <cmath>

#include "lcmtypes/text/number.hpp"
#include "processors/analysis/heldout.hpp"
#include "processors/model/json.hpp"

namespace gyrocal::analysis {

using Eigen::Index;
using Eigen::VectorXd;

ValidationResult Validate(const SensorRun& run, const model::CoeffSet& set,
                          const std::string& model_origin, const BinOptions& o) {
    ValidationResult r;
    r.sensor_id = run.sensor_id;
    r.model_origin = model_origin;
    r.power_on = run.power_on_source;
    const model::Evaluator check_offset(set.offset), check_sens(set.sensitivity);  // throw early
    const BinnedRun binned(run, o);
    r.n_bins = static_cast<int>(binned.size());
    if (binned.size() < 2) {
        r.notes.push_back("fewer than 2 still bins of " + std::to_string(o.bin_s) + " s");
        return r;
    }
    std::vector<Index> rows(binned.size());
    std::vector<int> stretch(binned.size());
    for (size_t i = 0; i < binned.size(); ++i) {
        const Bin& b = binned.bins()[i];
        rows[i] = static_cast<Index>(i);
        stretch[i] = b.segment;
        r.temp_min_c = std::min(std::isnan(r.temp_min_c) ? INFINITY : r.temp_min_c, b.temp_c);
        r.temp_max_c = std::max(std::isnan(r.temp_max_c) ? -INFINITY : r.temp_max_c, b.temp_c);
        if (!check_offset.InRange(b.temp_c)) ++r.n_bins_outside_range;
    }
    r.n_stretches = binned.bins().back().segment + 1;
    const VectorXd resid = detail::Residuals(binned, set.offset, rows);
    if (!resid.allFinite()) {
        r.notes.push_back("the model needs an input this run does not have (e.g. supply_v)");
        return r;
    }
    const ErrorFigures e = detail::ErrorsOn(binned, resid, rows, stretch, set.sensitivity);
    r.offset_rms_v = e.offset_rms_v;
    r.rate_rms_dps = e.rate_rms_dps;
    r.drift_dph = e.drift_dph;
    r.floor_offset_rms_v = NoiseFloor(binned.bins(), resid).offset_rms_v;
    const double inv_s = detail::MeanInverseSensitivity(binned, set.sensitivity, rows);
    r.floor_rate_rms_dps = r.floor_offset_rms_v * inv_s;
    r.floor_drift_dph =
        r.floor_rate_rms_dps * 3600.0 / std::sqrt(static_cast<double>(r.n_bins) / r.n_stretches);
    if (r.n_bins_outside_range > 0)
        r.notes.push_back(std::to_string(r.n_bins_outside_range) +
                          " bins outside the model's valid range (extrapolated)");
    if (run.power_on_assumed)
        r.notes.push_back("time since power-on counted from the first sample (no power-on record)");
    return r;
}

using model::JsonNumber;

nlohmann::json ToJson(const ValidationResult& r) {
    return {{"sensor_id", r.sensor_id},
            {"model_origin", r.model_origin},
            {"bins", r.n_bins},
            {"stretches", r.n_stretches},
            {"bins_outside_range", r.n_bins_outside_range},
            {"temp_min_c", JsonNumber(r.temp_min_c)},
            {"temp_max_c", JsonNumber(r.temp_max_c)},
            {"offset_rms_v", JsonNumber(r.offset_rms_v)},
            {"rate_rms_dps", JsonNumber(r.rate_rms_dps)},
            {"drift_dph", JsonNumber(r.drift_dph)},
            {"floor_offset_rms_v", JsonNumber(r.floor_offset_rms_v)},
            {"floor_rate_rms_dps", JsonNumber(r.floor_rate_rms_dps)},
            {"floor_drift_dph", JsonNumber(r.floor_drift_dph)},
            {"power_on", r.power_on},
            {"notes", r.notes}};
}

std::string FormatValidation(const ValidationResult& r) {
    std::string out = "sensor " + r.sensor_id + ": model " + r.model_origin + "\n";
    out += text::Printf("  %d still bins in %d stretches, %s..%s degC\n", r.n_bins, r.n_stretches,
                        text::SigOrDash(r.temp_min_c, 3).c_str(),
                        text::SigOrDash(r.temp_max_c, 3).c_str());
    out +=
        text::Printf("  %-12s %14s %14s %12s\n", "", "offset_rms_v", "rate_rms_dps", "drift_dph");
    out += text::Printf(
        "  %-12s %14s %14s %12s\n", "error", text::SigOrDash(r.offset_rms_v, 3).c_str(),
        text::SigOrDash(r.rate_rms_dps, 3).c_str(), text::SigOrDash(r.drift_dph, 3).c_str());
    out += text::Printf("  %-12s %14s %14s %12s\n", "floor",
                        text::SigOrDash(r.floor_offset_rms_v, 3).c_str(),
                        text::SigOrDash(r.floor_rate_rms_dps, 3).c_str(),
                        text::SigOrDash(r.floor_drift_dph, 3).c_str());
    out += "  power-on: " + r.power_on + "\n";
    for (const std::string& n : r.notes) out += "  note: " + n + "\n";
    return out;
}

}  // namespace gyrocal::analysis
