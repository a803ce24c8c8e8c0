#pragma once
// A stored run as the analysis reads it: for each sensor, every raw sample, the encoder readings,
// the chamber's air temperature (chamber_states.air_c; NULL readings skipped and counted), the
// power records, the plateaus and sensitivity points (analysis::BuildSensorRun), so that
// `gyrocal analyze` and `gyrocal validate` see one definition of a run's still data.
#include <map>
#include <string>
#include <vector>

#include "processors/analysis/bins_incremental.hpp"
#include "processors/analysis/run_data.hpp"
#include "store/db/query.hpp"

namespace gyrocal::cli {

// sensors: the ones wanted (others are skipped while reading). Throws db::NotFound for an
// unknown run.
std::map<std::string, analysis::SensorRun> LoadSensorRuns(db::Db& db, const db::RunDetail& detail,
                                                          const std::vector<std::string>& sensors);

// The same run binned as it is read (analysis/bins_incremental.hpp): memory per bin, not per
// sample (~0.25 MB per unit-hour), for runs too long to hold (a day of many units). The rows come
// in reception order, as the live fitter received them. Snapshot(id).Analyze(options) is then
// the analysis of `gyrocal analyze` (the header says what is exact and what is approximated).
analysis::RunBinner LoadBinnedRun(db::Db& db, const db::RunDetail& detail,
                                  const std::vector<std::string>& sensors,
                                  const analysis::IncrementalOptions& options);

}  // namespace gyrocal::cli
