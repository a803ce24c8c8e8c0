#pragma once
// Queries of the fitter's reports and the units' noise estimates (schema v5), for
// `gyrocal show`, `gyrocal analyze --plot` and anyone else. Bound parameters only.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/db/rows.hpp"
#include "store/db/sqlite_db.hpp"

namespace gyrocal::db {

struct FitReportInfo {
    int64_t fit_report_row_id = 0;
    FitReportRow report;  // with its exclusions and repeatability
};

struct NoiseInfo {
    int64_t noise_row_id = 0;
    NoiseRow noise;  // with its Allan points
    // [V/(deg/s)] at T0 of the run's newest fitter set of the sensor (v_noise); none without a set
    std::optional<double> sensitivity_v_per_dps;
};

// The final report of each sensor and source of a run (v_fit_final), by sensor then source.
std::vector<FitReportInfo> RunFitReports(Db& db, const std::string& run_id);
// The newest noise estimate of each sensor of a run (v_noise), by sensor.
std::vector<NoiseInfo> RunNoise(Db& db, const std::string& run_id);

}  // namespace gyrocal::db
