#pragma once
// Pictures of an analysis (what `gyrocal analyze --plot` draws), as figures of the project's one
// plotting path (plot/figure.hpp: tables and series, drawn by gnuplot). This library builds the
// figures only.
//
// Per sensor, on the still bins of the run (bins.hpp, the unit the analysis worked on):
//   <id>_residual_time     residual [mV] vs time since the first sample [h], before and after
//   <id>_residual_temp     residual [mV] vs temperature [degC], before and after
//   <id>_effect_<effect>   for each added offset effect: the partial residual
//                            y - (extended model without this term)            [mV]
//                          against the term's regressor (e.g. dT/dt [degC/s]), with the fitted
//                          effect c * regressor drawn over it. The partial residual is exactly
//                          what the term is fitted to, so a good fit lies along the line.
//   <id>_periodogram       amplitude [mV] of the sinusoid fitted to the final residual at each
//                          period [s] (log axis), the peak marked and labelled "peak: period P s,
//                          amplitude A mV"
//   <id>_autocorr          the final residual's autocorrelation against lag [s] within contiguous
//                          stretches, with the +-1.96/sqrt(bins) band white noise stays in
// "before" = the declared model fitted on all bins; "after" = the extended model fitted on all
// bins (the same when nothing was added).
// Data tables: <id>_residual (time_h temp_c resid_before_mv resid_after_mv, shared by the two
// residual figures), <id>_effect_<effect> (regressor partial_resid_mv fitted_effect_mv),
// <id>_periodogram (+ _peak: period_s amplitude_mv), <id>_autocorr (lag_s autocorr white_lo
// white_hi).
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/run_data.hpp"
#include "processors/plot/figure.hpp"

namespace gyrocal::analysis {

// The residual of each bin before and after (the <id>_residual table above), on the bins
// `result` was computed from.
plot::Table ResidualTable(const BinnedRun& binned, const SensorResult& result);

// `run` and `options` must be those `result` was computed from (the bins are rebuilt here).
std::vector<plot::Figure> MakePlots(const SensorRun& run, const SensorResult& result,
                                    const AnalysisOptions& options = AnalysisOptions::Defaults());

}  // namespace gyrocal::analysis
