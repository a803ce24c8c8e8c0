#pragma once
// The sensitivity side of the analysis: the declared sensitivity model on the accepted rotation
// points (weighted least squares with their standard errors; the polynomial degree is capped by
// the number of distinct temperatures) and the sf_asymmetry candidate, a "direction" term
// (+1 positive rotation, -1 negative). With known standard errors the statistic is
// z^2 = c^2 / var(c), var inflated by chi2/dof of the extended fit when that exceeds 1 (errors
// understated); cross-validation leaves out one temperature level at a time.
#include <optional>
#include <string>

#include "processors/analysis/analyze.hpp"
#include "processors/fit/fit.hpp"

namespace gyrocal::analysis {

struct SensitivityOutcome {
    std::optional<model::Model> declared;
    std::optional<model::Model> extended;  // declared + direction when added, else declared
    CandidateResult candidate;             // effect sf_asymmetry
    std::optional<AddedEffect> added;
    double rel_rms_before = kNan, rel_rms_after = kNan;
    double chi2_dof_before = kNan, chi2_dof_after = kNan;
    int n_points = 0;
    std::string problem;  // why there is no declared model ("" when there is)
};

// A rotation as a point of the sensitivity fit: y = sensitivity_v_per_dps with its standard
// error, at temp_c, the direction as an input (the sf_asymmetry term's).
fit::FitPoint SensitivityFitPoint(const SensitivityInput& s);

SensitivityOutcome AnalyzeSensitivity(const std::vector<SensitivityInput>& points,
                                      const AnalysisOptions& options);

}  // namespace gyrocal::analysis
