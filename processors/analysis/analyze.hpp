#pragma once
// Model discovery on one sensor's run: what effect does the declared model lack?
//
// 1. Declared model: the offset terms (default the seed's {1, dT, dT^2}) fitted on the plateau
//    means by weighted least squares as the fitter does (T0 = mid-range rounded to 5 degC); the
//    sensitivity terms fitted on the accepted rotation points.
// 2. Residual of that model on ALL still data, ramps included, in bins (bins.hpp).
// 3. Candidates, each a term of the model registry (model/terms.hpp) so the compensator and the
//    exports evaluate the extended model with the same code:
//      temp_rate    -> "dTdt"        offset follows the measured dT/dt      [V/(degC/s)]
//      hysteresis   -> "heating"     +-1 on the heating / cooling branch     [V]
//      temp_cubic   -> "dT^3"                                               [V/degC^3]
//      supply       -> "supply"      supply_v - 5 V, only where recorded     [V/V]
//      warmup       -> "warmup(tau)" exp(-t_on/tau), tau by a 1-D search     [V]
//      sf_asymmetry -> "direction"   on the sensitivity points               [V/(deg/s)]
// 4. Decision (forward selection): with the current terms fitted on all bins, each remaining
//    offset candidate is added in turn and judged by
//      (a) z^2 = c^2 / var(c), var from the autocorrelation-robust covariance (regress.hpp),
//          against min_z2 (default 25: 5 sigma, because six candidates are tried per step, the
//          warmup tau is searched, and HAC under-estimates variance with few effective blocks);
//      (b) blocked cross-validation: the mean squared out-of-block prediction error must drop by
//          more than min_cv_gain (a fraction) - an effect must predict data it did not see.
//      (c) its size on this data exceeds min_effect_floor_ratio x the noise floor.
//    All must pass. The best passing candidate (smallest residual sum of squares) is added, then
//    the rest are re-tested with it in the model; repeat until none passes. In the forward steps
//    the noise of (a) is the residual of the model with ALL remaining candidates in (stepwise
//    regression's full-model error), so a second missing effect does not pass for noise; at the end
//    every added term is re-tested with all the others in and its own model's residuals (backward
//    elimination) and removed when it no longer passes (a). Before adding, the best one's
//    regressor is compared with every other remaining candidate's after projecting out the
//    model: |correlation| > max_collinearity means the data cannot tell them apart: both are
//    reported "ambiguous" with the measurement that would separate them, and neither is added.
//    sf_asymmetry is judged the same way on the sensitivity points (known standard errors,
//    inflated by chi2/dof when above 1; leave-one-temperature-out cross-validation).
// 5. Errors before/after on a held-out stretch (the last holdout_fraction of the still bins):
//    both models re-fitted on the data before it only, applied to it: offset RMS [V], rate RMS
//    [deg/s] (residual / sensitivity), integrated-angle drift |sum rate*dt| / duration [deg/h];
//    and the floor from the scatter inside plateaus (bins.hpp; with effects added, of the extended
//    model's residuals). "Before" is the declared model on the plateaus before the stretch;
//    "after" the extended terms on the bins before it (equal to before when nothing was added).
//    The term CHOICE (step 4) saw all the data; the coefficients behind the figures did not.
//    time_since_power_s is counted from the run's first sample (the power-on proxy).
// 6. Whatever cannot be tested says why (could_not_test); nothing is ever invented to fill a gap.
#include <optional>
#include <string>
#include <vector>

#include "bins.hpp"
#include "model/convert.hpp"
#include "model/model.hpp"
#include "run_data.hpp"

namespace gyrocal::analysis {

struct AnalysisOptions {
    BinOptions bins = BinOptions::Defaults();
    std::vector<std::string> offset_terms = {"1", "dT", "dT^2"};       // declared model
    std::vector<std::string> sensitivity_terms = {"1", "dT", "dT^2"};  // (fewer if levels lack)
    double min_z2 = 25.0;                                              // see (a) above
    double min_cv_gain = 0.02;  // [1] relative drop of blocked-CV MSE
    int cv_blocks = 10;
    double cv_guard_s = 60.0;       // [s] bins this close to a held-out block are not trained on
    double hac_lag_s = 300.0;       // [s] Newey-West window (the slow noise's correlation time)
    double max_collinearity = 0.9;  // |projected correlation| above: ambiguous
    // (c) practical size: the effect's RMS on this data must exceed this multiple of the noise
    // floor (bins.hpp); a smaller one cannot measurably improve a compensation, and slow noise
    // (bias instability with ~1000 s correlation) can mimic a slow regressor (supply drift,
    // warm-up) at about that size in one run. Skipped when the floor is unknown.
    double min_effect_floor_ratio = 1.0;
    double holdout_fraction = 0.25;        // last fraction of still bins held out for before/after
    double min_ramp_c_per_s = 1.0 / 60.0;  // [degC/s] |dT/dt| that makes a bin a ramp bin
    int min_ramp_bins = 6;                 // temp_rate needs this many ramp bins
    double warmup_tau_min_s = 30.0;        // [s] 1-D search range of the warm-up time constant
    double warmup_tau_max_s = 3000.0;
    double warmup_max_tau_fraction = 0.1;  // [1] and at most this fraction of the still span
    double same_level_tolerance_c = 1.0;   // [degC] sensitivity points this close: one temperature
    static AnalysisOptions Defaults() { return {}; }
    std::string Problem() const;  // "" when valid
};

enum class Decision { kAdded, kRejected, kAmbiguous, kNotTested };
const char* ToString(Decision d);

struct CandidateResult {
    std::string effect;  // temp_rate, hysteresis, temp_cubic, supply, warmup, sf_asymmetry
    std::string term;    // registry name, e.g. "dTdt", "warmup(312)"
    Decision decision = Decision::kNotTested;
    double z2 = kNan;            // statistic (a) at the step it was decided
    double cv_gain = kNan;       // (b) relative CV-MSE drop
    int step = 0;                // selection step it was decided at (1-based)
    std::string note;            // why not tested / ambiguous with what / how to separate
    double effect_rms_v = kNan;  // [V] size of the effect on this data (coefficient * RMS of its
                                 // regressor after projecting out the model)
};

struct AddedEffect {
    std::string effect, term, unit;
    double coefficient = kNan;  // [unit]
    double stderr_ = kNan;      // [unit]
};

struct ErrorFigures {
    double offset_rms_v = kNan;
    double rate_rms_dps = kNan;
    double drift_dph = kNan;
};

struct SensorResult {
    std::string sensor_id;
    std::string verdict;  // "no missing effect", "missing effect: a, b", "ambiguous: ...", "not
                          // analysed: ..."
    std::vector<CandidateResult> candidates;
    std::vector<AddedEffect> added;
    ErrorFigures error_before, error_after;  // on the held-out stretch
    double floor_offset_rms_v = kNan;
    double floor_rate_rms_dps = kNan;
    double floor_drift_dph = kNan;     // white-noise lower bound over the held-out stretch
    // What error_after should be if the extended model is right: the training fit's residual
    // variance (white and slow noise as that fit saw them) plus its prediction variance on the
    // held-out bins (mean x' Cov x, robust covariance). The floor is the white scatter a perfect
    // model would leave; this adds what fitting on part of the run costs, chiefly when the
    // held-out stretch extrapolates in temperature. error_after far above it: the model is still
    // wrong, or slow noise (bias instability over ~1000 s, which neither the floor nor a 300 s
    // robust covariance fully sees) is large on this run.
    double expected_after_offset_rms_v = kNan;
    double expected_after_rate_rms_dps = kNan;
    double prediction_rms_v = kNan;  // the prediction part alone
    double prediction_rms_dps = kNan;
    double residual_all_rms_v = kNan;  // declared model on all still bins (step 2)
    double residual_all_extended_rms_v = kNan;
    double sens_rel_rms_before = kNan, sens_rel_rms_after = kNan;  // [1] sensitivity residuals
    double sens_chi2_dof_before = kNan, sens_chi2_dof_after = kNan;
    int n_bins = 0, n_holdout_bins = 0, n_plateaus_used = 0, n_sensitivity_points = 0;
    double bin_s = 0.0;
    std::vector<std::string> could_not_test;
    std::vector<std::string> notes;
    std::optional<model::Model> declared_offset, declared_sensitivity;
    std::optional<model::Model> extended_offset, extended_sensitivity;  // fitted on all data
    // The held-out split and the models the before/after figures used (fitted before it), so a
    // benchmark can put other methods on exactly the same data.
    int64_t holdout_start_utime = 0;  // [us] first held-out bin
    int64_t train_end_utime = 0;      // [us] end of the last training bin
    std::optional<model::Model> holdout_before_offset, holdout_after_offset;
};

// Never throws on bad data (it says what it could not do); throws std::invalid_argument on bad
// options (Problem()).
SensorResult Analyze(const SensorRun& run,
                     const AnalysisOptions& options = AnalysisOptions::Defaults());

// The extended model as a coefficient set (source "analysis:<analysis_id>"); nullopt when the
// result has no usable extended offset and sensitivity model.
std::optional<model::CoeffSet> ExtendedCoeffSet(const SensorResult& result,
                                                const std::string& run_id,
                                                const std::string& analysis_id, int64_t utime);

}  // namespace gyrocal::analysis
