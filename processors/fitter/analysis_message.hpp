#pragma once
// The closed loop's result as a bus message (analysis_t on ANALYSIS_<id>): what the analysis of
// every still sample found, the error before and after on held-out data, and the set it made.
// The analysis' JSON (analysis/report.hpp, as `gyrocal analyze --json` writes it) with the still
// bins' residual before and after added ("residual_bins": the report draws it).
#include <string>

#include "gyrocal/analysis_t.hpp"
#include "processors/fitter/ramp_fitter.hpp"

namespace gyrocal::fitter {

// nullopt when no analysis ran (no samples of the unit).
std::optional<analysis_t> AnalysisMessage(const RampFitResult& result, const std::string& run_id,
                                          const std::string& source);

}  // namespace gyrocal::fitter
