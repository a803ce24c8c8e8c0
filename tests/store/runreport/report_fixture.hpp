#pragma once
// A database with one run whose answers are known, written through the store's own writer:
//   run "R7" from a CSV file (input and its SHA-256 in the configuration), host "daq-pc", limits
//   stored with the run (kLimitsJson), plateau slow noise 0.01 deg/s;
//   S01: five plateaus on the curve of its coefficient set with residuals of +0.5, -0.5, +1, -1, 0
//        times their floor (so max_residual_rms_over_floor measures sqrt(2.5 / 2)), ten turns of
//        which one is refused (reason with HTML in it), the fitter's set (offset kOffset,
//        sensitivity kSens), an analysis "missing effect: supply" with its extended set;
//   S02: two plateaus and nothing fitted (fails every limit that needs a calibration).
#include <string>
#include <vector>

namespace gyrocal::testing {

inline constexpr const char* kRunId = "R7";
inline constexpr const char* kLimitsJson =
    R"({"description":"fixture limits","max_residual_rms_over_floor":1.5,"max_offset_change_dps":10,)"
    R"("min_plateaus":5,"min_turns":9,"no_unexplained_residual":true})";
inline constexpr const char* kRefusal = "<b>angle</b> 87.1 deg is not within 1 deg of 90";
inline constexpr double kSlowNoiseDps = 0.01;
inline const std::vector<double> kOffset = {2.5, 4e-4,
                                            6e-6};        // about 25 degC [V, V/degC, V/degC^2]
inline const std::vector<double> kSens = {0.0057, 2e-6};  // [V/(deg/s), ../degC]
inline const std::vector<double> kPlateauTemps = {-40, -10, 25, 55, 85};
inline const std::vector<double> kResidualSigmas = {0.5, -0.5, 1, -1, 0};
inline constexpr double kSemV = 4e-5;

void WriteReportDb(const std::string& path);

}  // namespace gyrocal::testing
