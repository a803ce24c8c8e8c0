#pragma once
// Internal to gyrocal_analysis: the outcome and its headline (analyze.hpp, step 9), from the
// held-out residual against the floor bound, the candidates that could not be tested, the generic
// features that explain held-out data and the residual diagnostics.
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"

namespace gyrocal::analysis::detail {

// The measurement that would make an untestable candidate testable.
std::string MeasurementToTest(const std::string& effect);

// bound^2 = floor^2 (1 + 9 k^2) + 9 prediction^2 (analyze.hpp, step 9); NaN without a floor.
double FloorBound(double floor_v, double prediction_v, double slow_ratio);

// Fills outcome, headline, verdict, untested/to_test, heldout_residual_rms_v, floor_bound_rms_v,
// excess_ratio, from every piece of evidence in res: the held-out residual against the floor
// bound (k from the run unless set), the generic features and the windows judged against the
// run's noise, the ambiguities. analysed: the offset candidates could be run at all.
void Conclude(bool analysed, const AnalysisOptions& o, SensorResult& res);

}  // namespace gyrocal::analysis::detail
