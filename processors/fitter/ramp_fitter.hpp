#pragma once
// The fitter of a ramp run (gyrocal-fitter --mode ramp): offset and sensitivity of each unit from
// EVERY still window of the run, not from plateaus.
//
// A ramp never holds a temperature, so there are no plateau means to fit; instead the run's raw
// samples, the table's encoder and the rotation estimator's sensitivity points are kept, and the
// analysis library (processors/analysis/analyze.hpp) does the fit: its still bins (10 s, the
// encoder decides still vs moving), its model inputs (dT/dt with its time constant, heating/cooling
// branch: model/inputs.hpp, the trackers the compensators run), its forward selection of the rate,
// branch, cubic, supply and warm-up terms on held-out blocks and its held-out confirmation, its
// autocorrelation-robust coefficient covariance, and its sensitivity fit on the rotation points.
// The set published is the analysis' extended model refitted on all bins: the same fitter and the
// same selection as `gyrocal analyze`, so a term is in a set only when the data showed it.
//
// When: during the run every refit_interval_s of data time once min_span_s of samples are in
// (sets as the run goes: the compensator and the sequencer's early stop use them), and once at the
// run's stop (the final set, with is_final reports). Memory: every sample of the run (about
// 40 bytes each: 14 MB per unit-hour at 100 Hz).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "analysis/analyze.hpp"
#include "analysis/run_data.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"

namespace gyrocal::fitter {

struct RampFitterOptions {
    analysis::AnalysisOptions analysis = analysis::AnalysisOptions::Defaults();
    analysis::BuildOptions build = analysis::BuildOptions::Defaults();
    double refit_interval_s = 600.0;  // [s] data time between fits during the run
    double min_span_s = 1200.0;       // [s] of a unit's samples before its first fit in the run
    static RampFitterOptions Defaults() { return {}; }
    std::string Problem() const;  // "" when valid, else the option and what is valid
};

struct RampFitResult {
    std::string sensor_id;
    std::optional<coeff_set_t> set;  // nullopt when no model could be fitted (report says why)
    fit_report_t report;
};

class RampFitter {
public:
    explicit RampFitter(RampFitterOptions options);  // throws std::invalid_argument on Problem()

    // The run's id (RUN_EVENT start). Samples heard before it are kept: they are the units at
    // rest at the start temperature, and the model inputs are tracked from the first sample.
    void StartRun(const std::string& run_id);
    void AddGyro(const std::string& sensor_id, const analysis::GyroSample& s);
    void AddEncoder(const analysis::EncoderSample& e);
    void AddSensitivity(const std::string& sensor_id, const analysis::SensitivityInput& p);

    // Data time advanced: the fits that are due (see above); empty outside a run.
    std::vector<RampFitResult> OnTime(int64_t utime);
    // RUN_EVENT stop/abort: the final fit of every unit heard (is_final), then the run's data are
    // dropped.
    std::vector<RampFitResult> Finish(int64_t stop_utime);
    // One unit's fit on everything so far (tests, benchmarks).
    RampFitResult Fit(const std::string& sensor_id, int64_t utime, bool is_final) const;

    const std::string& run_id() const { return run_id_; }
    size_t samples(const std::string& sensor_id) const;

private:
    struct Unit {
        std::vector<analysis::GyroSample> samples;
        std::vector<analysis::SensitivityInput> points;
        int64_t last_fit_utime = -1;
    };
    RampFitterOptions options_;
    std::string run_id_;
    std::map<std::string, Unit> units_;
    std::vector<analysis::EncoderSample> encoder_;
};

}  // namespace gyrocal::fitter
