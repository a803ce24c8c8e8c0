#pragma once
// A unit's calibration against acceptance limits (limits.hpp): each limit, the measured value and
// pass / FAIL / not evaluated, and the unit's outcome. Never a silent pass: a limit whose evidence
// this run does not have (no analysis for no_unexplained_residual, no degree of freedom for the
// residual) is "not evaluated" and the unit is then not a pass; a limit whose evidence the
// calibration should have but lacks (no coefficient set, a nominal sensitivity without
// uncertainty) fails.
//
// The measures, on the unit's final calibration (its newest coefficient set of the run: on a
// plateau run with the closed loop, the set fitted on every still sample; the plateau set stays
// beside it) and, for what is about the plateaus, on its plateau set:
//   residual over floor  sqrt(chi2 / dof) of the plateau set, chi2 = sum ((y_i - offset(T_i)) /
//                        sigma_i)^2 over the plateaus that set was fitted on, sigma_i = the
//                        plateau's standard error combined in quadrature with the run's plateau
//                        slow noise (slow_noise_dps x the fitted sensitivity at T_i), dof =
//                        plateaus - terms;
//   offset change        (max - min of offset(T)) / |S(T_mid)| over [temp_min_c, temp_max_c] of the
//                        offset model, on a grid of 201 temperatures;
//   sensitivity uncert.  max over the sensitivity model's range of 100 sqrt(var S(T)) / |S(T)|,
//                        var = phi' C phi (model::Evaluator);
//   plateaus, turns      ids the plateau set lists, ids the final set lists;
//   held-out error       the final set's closed-loop analysis (error_after: rate RMS of 10 s bins,
//                        drift), NaN (not evaluated) for a set no analysis made;
//   unexplained residual the newest analysis' outcome (analyses.outcome), never its headline's
//                        wording: adequate / explained pass; partly explained / unexplained
//                        residual and ambiguous fail (the headline is the note); not testable is
//                        not evaluated
//                        (with what to measure); no analysis, an analysis stored before outcomes
//                        existed, or an outcome this version does not know: not evaluated, named.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "processors/acceptance/limits.hpp"
#include "processors/model/model.hpp"

namespace gyrocal::acceptance {

struct PlateauPoint {
    double temp_c = NAN;       // [degC] plateau mean temperature
    double gyro_mean_v = NAN;  // [V]
    double gyro_sem_v = NAN;   // [V] standard error of the mean from the plateau window
};

struct UnitEvidence {
    std::string sensor_id;
    bool has_calibration = false;      // false: no coefficient set for the unit in this run
    model::Model offset, sensitivity;  // the final set
    // The plateau set (the final set itself on a run without the closed loop): what the
    // plateau checks judge.
    model::Model plateau_offset, plateau_sensitivity;
    std::vector<PlateauPoint> plateaus;           // those the plateau set was fitted on
    int n_plateaus = 0;                           // plateau ids the plateau set lists
    int n_turns = 0;                              // rotation ids the set lists
    double plateau_slow_noise_dps = 0;            // [deg/s] as the run declared it (0 = none)
    std::optional<std::string> analysis_verdict;  // newest analysis of the unit, if any: headline
    std::optional<std::string> analysis_outcome;  // its outcome; nullopt: none stored (older)
    std::vector<std::string> analysis_to_test;    // not testable: what measurement would test it
    bool analysis_stored_set = false;             // the analysis stored its extended model as a set
    // [deg/s], [deg/h] the final set's held-out error from the analysis that made it; NaN: none.
    double final_heldout_rate_rms_dps = NAN;
    double final_heldout_drift_dph = NAN;
    std::string final_heldout_note;  // why NaN
};

enum class Outcome { kPass, kFail, kNotEvaluated };
const char* ToString(Outcome o);  // "pass", "FAIL", "not evaluated"

// A measured value, or NaN with why it could not be measured.
struct Measure {
    double value = NAN;
    std::string note;
};
Measure ResidualOverFloor(const UnitEvidence& unit);
Measure OffsetChangeDps(const model::Model& offset, const model::Model& sensitivity);
Measure MaxSensitivityRelUncertaintyPct(const model::Model& sensitivity);

struct Check {
    std::string key, unit, kind;  // as LimitDef
    double limit = NAN;           // the limit (1 for require)
    double measured = NAN;        // NaN when not measured
    std::string measured_text;    // what was measured, for people (e.g. the verdict)
    Outcome outcome = Outcome::kNotEvaluated;
    std::string note;  // why not evaluated / why it failed, when useful
};

struct UnitVerdict {
    std::string sensor_id;
    std::vector<Check> checks;                 // in LimitDefs() order, only the limits given
    Outcome outcome = Outcome::kNotEvaluated;  // FAIL if any fails, else not evaluated if any is
};

UnitVerdict Evaluate(const Limits& limits, const UnitEvidence& unit);

// "S02: max_offset_change_dps 3.4 > 3 deg/s; min_turns 6 < 10": the checks that did not pass
// (failed or not evaluated), or "S01: pass".
std::string Summary(const UnitVerdict& verdict);

}  // namespace gyrocal::acceptance
