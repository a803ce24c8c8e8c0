#pragma once
// Pictures of an analysis (issue 6, "Show it"): the data files and gnuplot scripts, as text. The
// caller writes them into one directory and runs gnuplot there (scripts name files relative to
// it); this library runs nothing and touches no file.
//
// Per sensor, on the still bins of the run (bins.hpp, the unit the analysis worked on):
//   <id>_residual_time     residual [mV] vs time since the first sample [h], before and after
//   <id>_residual_temp     residual [mV] vs temperature [degC], before and after
//   <id>_effect_<effect>   for each added offset effect: the partial residual
//                            y - (extended model without this term)            [mV]
//                          against the term's regressor (e.g. dT/dt [degC/s]), with the fitted
//                          effect c * regressor drawn over it. The partial residual is exactly
//                          what the term is fitted to, so a good fit lies along the line.
// "before" = the declared model fitted on all bins; "after" = the extended model fitted on all
// bins (the same when nothing was added).
// Every script writes <name>.png (pngcairo) and <name>.svg. Missing values are written as "?".
#include <string>
#include <vector>

#include "analyze.hpp"
#include "run_data.hpp"

namespace gyrocal::analysis {

struct PlotFile {
    std::string name;  // file name inside the plot directory (no path)
    std::string text;
};

struct PlotSet {
    std::vector<PlotFile> files;       // data files (.dat) and scripts (.gp)
    std::vector<std::string> scripts;  // names of the .gp files to run, in order
    std::vector<std::string> images;   // names of the images the scripts write
};

// `run` and `options` must be those `result` was computed from (the bins are rebuilt here).
PlotSet MakePlots(const SensorRun& run, const SensorResult& result,
                  const AnalysisOptions& options = AnalysisOptions::Defaults());

}  // namespace gyrocal::analysis
