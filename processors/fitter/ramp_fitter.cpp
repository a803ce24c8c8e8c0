#include "ramp_fitter.hpp"

#include <cmath>
#include <stdexcept>

#include "model/convert.hpp"

namespace gyrocal::fitter {
namespace {

std::string Terms(const model::Model& m) {
    std::string s;
    for (const std::string& t : m.term_names) s += (s.empty() ? "" : ", ") + t;
    return "{" + s + "}";
}

fit_report_t EmptyReport(const std::string& sensor_id, const std::string& run_id, int64_t utime,
                         bool is_final) {
    fit_report_t r;
    r.utime = utime;
    r.sensor_id = sensor_id;
    r.run_id = run_id;
    r.coeff_set_id = -1;
    r.source = "fitter";
    r.is_final = is_final;
    r.status = "none";
    r.slow_noise_v = NAN;
    r.slow_noise_dps = NAN;
    r.slow_noise_source =
        "none: the ramp fit's coefficient covariance is autocorrelation-robust (analysis HAC)";
    r.num_excluded = 0;
    r.num_repeats = 0;
    return r;
}

}  // namespace

std::string RampFitterOptions::Problem() const {
    if (std::string p = analysis.Problem(); !p.empty()) return "analysis: " + p;
    if (!(refit_interval_s >= 10.0 && refit_interval_s <= 86400.0))
        return "refit interval " + std::to_string(refit_interval_s) + " s: valid is 10..86400";
    if (!(min_span_s >= 0.0 && min_span_s <= 86400.0))
        return "min span " + std::to_string(min_span_s) + " s: valid is 0..86400";
    return "";
}

RampFitter::RampFitter(RampFitterOptions options) : options_(std::move(options)) {
    if (const std::string p = options_.Problem(); !p.empty())
        throw std::invalid_argument("ramp fitter: " + p);
}

void RampFitter::StartRun(const std::string& run_id) {
    run_id_ = run_id;
    for (auto& [id, u] : units_) u.last_fit_utime = -1;
}

void RampFitter::AddGyro(const std::string& sensor_id, const analysis::GyroSample& s) {
    units_[sensor_id].samples.push_back(s);
}

void RampFitter::AddEncoder(const analysis::EncoderSample& e) { encoder_.push_back(e); }

void RampFitter::AddSensitivity(const std::string& sensor_id, const analysis::SensitivityInput& p) {
    units_[sensor_id].points.push_back(p);
}

size_t RampFitter::samples(const std::string& sensor_id) const {
    const auto it = units_.find(sensor_id);
    return it == units_.end() ? 0 : it->second.samples.size();
}

std::vector<RampFitResult> RampFitter::OnTime(int64_t utime) {
    std::vector<RampFitResult> out;
    if (run_id_.empty()) return out;
    for (auto& [id, u] : units_) {
        if (u.samples.empty()) continue;
        const double span_s = 1e-6 * static_cast<double>(utime - u.samples.front().utime);
        if (span_s < options_.min_span_s) continue;
        if (u.last_fit_utime >= 0 &&
            1e-6 * static_cast<double>(utime - u.last_fit_utime) < options_.refit_interval_s)
            continue;
        u.last_fit_utime = utime;
        out.push_back(Fit(id, utime, false));
    }
    return out;
}

std::vector<RampFitResult> RampFitter::Finish(int64_t stop_utime) {
    std::vector<RampFitResult> out;
    if (run_id_.empty()) return out;
    for (const auto& [id, u] : units_) out.push_back(Fit(id, stop_utime, true));
    units_.clear();
    encoder_.clear();
    run_id_.clear();
    return out;
}

RampFitResult RampFitter::Fit(const std::string& sensor_id, int64_t utime, bool is_final) const {
    RampFitResult res;
    res.sensor_id = sensor_id;
    res.report = EmptyReport(sensor_id, run_id_, utime, is_final);
    const auto it = units_.find(sensor_id);
    if (it == units_.end() || it->second.samples.empty()) {
        res.report.reason = "no samples of this unit";
        return res;
    }
    const Unit& u = it->second;
    const analysis::SensorRun run =
        analysis::BuildSensorRun(sensor_id, u.samples, encoder_, {}, u.points, {}, options_.build);
    const analysis::SensorResult r = analysis::Analyze(run, options_.analysis);
    // The set's id is its newest input; a final set is the stop event's (coeff_set_t).
    const int64_t newest = is_final ? utime : run.samples.empty() ? utime : run.samples.back().utime;
    std::optional<model::CoeffSet> set = analysis::ExtendedCoeffSet(r, run_id_, "ramp", newest);
    if (!set) {
        std::string why = r.verdict;
        for (const std::string& c : r.could_not_test) why += "; " + c;
        res.report.reason = "no model: " + why;
        return res;
    }
    set->source = "fitter";
    set->offset.method = "ramp";
    set->sensitivity.method = "ramp";
    for (const auto& p : u.points)
        if (p.accepted) set->rotation_ids.push_back(p.rotation_id);
    res.set = model::ToMsg(*set);
    res.report.utime = newest;
    res.report.coeff_set_id = set->coeff_set_id;
    res.report.status = "complete";
    res.report.offset_detail = "ramp fit on " + std::to_string(r.n_bins) + " still bins of " +
                               std::to_string(r.bin_s) + " s: terms " + Terms(set->offset) +
                               "; " + r.verdict;
    res.report.sensitivity_detail = "on " + std::to_string(r.n_sensitivity_points) +
                                    " rotation points: terms " + Terms(set->sensitivity);
    return res;
}

}  // namespace gyrocal::fitter
