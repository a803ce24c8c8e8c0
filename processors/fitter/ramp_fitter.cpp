#include "processors/fitter/ramp_fitter.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "processors/model/convert.hpp"

namespace gyrocal::fitter {
namespace {

std::string Terms(const model::Model& m) {
    std::string s;
    for (const std::string& t : m.term_names) s += (s.empty() ? "" : ", ") + t;
    return "{" + s + "}";
}

fit_report_t EmptyReport(const FitJob& job, const std::string& source) {
    fit_report_t r;
    r.utime = job.utime;
    r.sensor_id = job.sensor_id;
    r.run_id = job.run_id;
    r.coeff_set_id = -1;
    r.source = source;
    r.is_final = job.is_final;
    r.status = "none";
    r.slow_noise_v = NAN;
    r.slow_noise_dps = NAN;
    r.slow_noise_source =
        "none: the fit on every still bin has an autocorrelation-robust covariance (analysis HAC)";
    r.num_excluded = 0;
    r.num_repeats = 0;
    return r;
}

analysis::IncrementalOptions BinnerOptions(const RampFitterOptions& o) {
    analysis::IncrementalOptions b = analysis::IncrementalOptions::For(o.analysis, o.width_ratio);
    b.build = o.build;
    b.max_cells = o.max_bins_per_unit;
    return b;
}

}  // namespace

RampFitterOptions RampFitterOptions::ClosedLoop() {
    RampFitterOptions o;
    o.refit_during_run = false;
    o.keep_after_stop = true;
    o.source = model::kClosedLoopSource;
    o.method = "analysis";
    return o;
}

std::string RampFitterOptions::Validate() const {
    if (std::string p = analysis.Validate(); !p.empty()) return "analysis: " + p;
    if (!(refit_interval_s >= 10.0 && refit_interval_s <= 86400.0))
        return "refit interval " + std::to_string(refit_interval_s) + " s: valid is 10..86400";
    if (!(min_span_s >= 0.0 && min_span_s <= 86400.0))
        return "min span " + std::to_string(min_span_s) + " s: valid is 0..86400";
    if (!(width_ratio > 1.0 && width_ratio <= 2.0))
        return "width ratio " + std::to_string(width_ratio) + ": valid is (1, 2]";
    if (source.empty() || method.empty()) return "source and method must not be empty";
    if (!(max_bins_per_unit == 0 || max_bins_per_unit >= 64))
        return "max bins per unit " + std::to_string(max_bins_per_unit) +
               ": valid is 0 (no limit) or at least 64";
    return "";
}

RampFitter::RampFitter(RampFitterOptions options) : options_(std::move(options)) {
    if (const std::string p = options_.Validate(); !p.empty())
        throw std::invalid_argument("ramp fitter: " + p);
    binner_ = std::make_unique<analysis::RunBinner>(BinnerOptions(options_));
}

void RampFitter::StartRun(const std::string& run_id) {
    if (stopped_) {  // the data kept after the previous run's stop are not this run's
        binner_ = std::make_unique<analysis::RunBinner>(BinnerOptions(options_));
        stopped_ = false;
    }
    run_id_ = run_id;
    last_fit_utime_.clear();
}

// After the stop (keep_after_stop) the samples are not the run's: the bins stay as they were.
void RampFitter::AddGyro(const std::string& sensor_id, const analysis::GyroSample& s) {
    if (!stopped_) binner_->AddGyro(sensor_id, s);
}

void RampFitter::AddEncoder(const motion::EncoderReading& e) {
    if (!stopped_) binner_->AddEncoder(e);
}

void RampFitter::AddSensitivity(const std::string& sensor_id, const analysis::SensitivityInput& p) {
    binner_->AddSensitivity(sensor_id, p);
}

void RampFitter::AddPower(const std::string& sensor_id, const analysis::PowerRecord& p) {
    if (!stopped_) binner_->AddPower(sensor_id, p);
}

void RampFitter::AddAir(const analysis::AirSample& a) {
    if (!stopped_) binner_->AddAir(a);
}

void RampFitter::AddPlateau(const std::string& sensor_id, const analysis::PlateauInput& p) {
    binner_->AddPlateau(sensor_id, p);
}

size_t RampFitter::samples(const std::string& sensor_id) const {
    const analysis::UnitBinner* u = binner_->unit(sensor_id);
    return u ? static_cast<size_t>(u->samples()) : 0;
}

FitJob RampFitter::Job(const std::string& sensor_id, int64_t utime, bool is_final) const {
    FitJob job;
    job.sensor_id = sensor_id;
    job.run_id = run_id_;
    job.is_final = is_final;
    job.utime = utime;
    if (const analysis::UnitBinner* u = binner_->unit(sensor_id)) {
        // The set's id is its newest input; a final set is the stop event's (coeff_set_t).
        if (!is_final && u->samples() > 0) job.utime = u->newest_utime();
        job.bins = binner_->Snapshot(sensor_id);
    }
    return job;
}

std::vector<FitJob> RampFitter::DueJobs(int64_t utime) {
    std::vector<FitJob> out;
    if (run_id_.empty() || stopped_ || !options_.refit_during_run) return out;
    for (const std::string& id : binner_->sensors()) {
        const analysis::UnitBinner* u = binner_->unit(id);
        if (!u->first_utime()) continue;
        const double span_s = 1e-6 * static_cast<double>(utime - *u->first_utime());
        if (span_s < options_.min_span_s) continue;
        const auto last = last_fit_utime_.find(id);
        if (last != last_fit_utime_.end() &&
            1e-6 * static_cast<double>(utime - last->second) < options_.refit_interval_s)
            continue;
        last_fit_utime_[id] = utime;
        out.push_back(Job(id, utime, false));
    }
    return out;
}

std::vector<FitJob> RampFitter::FinishJobs(int64_t stop_utime) {
    std::vector<FitJob> out;
    if (run_id_.empty()) return out;
    if (!stopped_) binner_->Flush();  // the end of the readings: decide every waiting bin
    stopped_ = true;
    // Every unit heard on its gyro channel (one known only from its points has nothing to fit).
    for (const std::string& id : binner_->sensors())
        if (binner_->unit(id)->raw_samples() > 0) out.push_back(Job(id, stop_utime, true));
    if (!options_.keep_after_stop) {
        binner_ = std::make_unique<analysis::RunBinner>(BinnerOptions(options_));
        run_id_.clear();
        stopped_ = false;
    }
    return out;
}

RampFitResult RampFitter::Run(const FitJob& job) const {
    RampFitResult res;
    res.sensor_id = job.sensor_id;
    res.report = EmptyReport(job, options_.source);
    if (job.bins.empty() || (job.bins.cells() == 0 && job.bins.run().n_raw_samples == 0)) {
        res.report.reason = "no samples of this unit";
        return res;
    }
    // The analysis at the bins' length (longer than the options' once max_bins_per_unit merged
    // them), its blocks at least as long as its checks need (10 bins held out, one bin early).
    analysis::AnalysisOptions ao = options_.analysis;
    if (job.bins.bin_s() != ao.bins.bin_s) {
        ao.bins.bin_s = job.bins.bin_s();
        ao.holdout_block_s = std::max(ao.holdout_block_s, 10.0 * ao.bins.bin_s);
        ao.early_block_s = std::max(ao.early_block_s, ao.bins.bin_s);
    }
    const analysis::BinnedRun binned = job.bins.Binned(ao.bins);
    analysis::SensorResult& r =
        res.analysis.emplace(analysis::AnalyzeBinned(job.bins.run(), binned, ao));
    if (ao.bins.bin_s != options_.analysis.bins.bin_s)
        r.notes.push_back("bins merged to " + std::to_string(static_cast<int>(ao.bins.bin_s)) +
                          " s to hold at most " + std::to_string(options_.max_bins_per_unit) +
                          " bins per unit");
    for (const std::string& a : job.bins.Approximations())
        r.notes.push_back("incremental bins: " + a);
    if (options_.carry_cubic) analysis::CarryForPrediction(binned, ao, "temp_cubic", "dT^3", r);
    res.residual = analysis::ResidualTable(binned, r);
    std::optional<model::CoeffSet> set =
        analysis::ExtendedCoeffSet(r, job.run_id, options_.method, job.utime);
    if (!job.withhold.empty()) {
        res.report.reason = "no set: " + job.withhold;
        return res;
    }
    if (!set) {
        std::string why = r.verdict;
        for (const std::string& c : r.could_not_test) why += "; " + c;
        res.report.reason = "no model: " + why;
        return res;
    }
    set->source = options_.source;
    set->offset.method = options_.method;
    set->sensitivity.method = options_.method;
    for (const auto& p : job.bins.run().sensitivities)
        if (p.accepted) set->rotation_ids.push_back(p.rotation_id);
    res.set = model::ToMsg(*set);
    res.report.coeff_set_id = set->coeff_set_id;
    res.report.status = "complete";
    res.report.offset_detail = "fit on " + std::to_string(r.n_bins) + " still bins of " +
                               std::to_string(r.bin_s) + " s: terms " + Terms(set->offset) + "; " +
                               r.verdict;
    res.report.sensitivity_detail = "on " + std::to_string(r.n_sensitivity_points) +
                                    " rotation points: terms " + Terms(set->sensitivity);
    return res;
}

std::vector<RampFitResult> RampFitter::OnTime(int64_t utime) {
    std::vector<RampFitResult> out;
    for (const FitJob& j : DueJobs(utime)) out.push_back(Run(j));
    return out;
}

std::vector<RampFitResult> RampFitter::Finish(int64_t stop_utime) {
    std::vector<RampFitResult> out;
    for (const FitJob& j : FinishJobs(stop_utime)) out.push_back(Run(j));
    return out;
}

RampFitResult RampFitter::Fit(const std::string& sensor_id, int64_t utime, bool is_final) const {
    return Run(Job(sensor_id, utime, is_final));
}

}  // namespace gyrocal::fitter
