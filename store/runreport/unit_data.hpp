#pragma once
// A run as the report and the acceptance check see it: per unit, everything the store holds
// about it (plateaus, turns, the calibration, other coefficient sets, analyses), taken from
// db::RunDetail (the query library: ShowRun). Pure: structs in, structs out.
//
// The calibration judged is the unit's final coefficient set from the fitter (the newest set whose
// source is not "analysis:<id>"): on a plateau run with the closed loop, the set fitted on every
// still sample (source "closed-loop"), with the plateau set (source "fitter", plateau means only)
// beside it; what is about the plateaus (their residual, their count) is judged on the plateau
// set. A `gyrocal analyze` set is shown beside them and judged through the analysis' verdict
// (no_unexplained_residual). The final set's held-out error comes from the analysis that made it
// (the analyses row linked to the set).
#include <optional>
#include <string>
#include <vector>

#include "processors/acceptance/evaluate.hpp"
#include "processors/acceptance/limits.hpp"
#include "store/db/query.hpp"

namespace gyrocal::runreport {

struct UnitData {
    std::string sensor_id;
    std::vector<db::PlateauRow> plateaus;         // every plateau of the unit in the run
    std::vector<db::SensitivityRow> turns;        // every turn, accepted or not
    std::optional<db::CoeffSetInfo> calibration;  // the final set
    std::optional<db::CoeffSetInfo> plateau_set;  // the newest set of source "fitter", when
                                                  // the final set is another (closed loop)
    std::vector<db::CoeffSetInfo> other_sets;     // every other set (older ones, analyses)
    // The analysis that made the final set (closed loop, ramp fit), when stored.
    std::optional<db::AnalysisRow> final_analysis;
    std::vector<db::AnalysisRow> analyses;  // oldest first
};

// The units of a run, by sensor id: those the run declared and any other with data in it.
std::vector<UnitData> Units(const db::RunDetail& detail);

// [deg/s] the plateau slow noise the run declared (configuration plateau_slow_noise_dps; the
// fitter added it to each plateau's standard error); 0 when the run did not declare one.
double PlateauSlowNoiseDps(const db::RunInfo& run);

acceptance::UnitEvidence Evidence(const UnitData& unit, double plateau_slow_noise_dps);

// Limits stored with a run (configuration key "acceptance_limits", written by gyrocal calibrate
// --limits). `problem` says why stored limits cannot be used (then `limits` is empty).
struct RunLimits {
    std::optional<acceptance::Limits> limits;
    std::string origin;   // where they came from, for people
    std::string problem;  // "" when fine
};
RunLimits StoredLimits(const db::RunInfo& run);

// Key of the run configuration that holds the limits (and of their file name and hash).
inline constexpr const char* kLimitsKey = "acceptance_limits";
inline constexpr const char* kLimitsFileKey = "acceptance_limits_file";

std::vector<acceptance::UnitVerdict> Accept(const db::RunDetail& detail,
                                            const acceptance::Limits& limits);

// "pass" when every unit passed; else "FAIL" when any failed; else "not evaluated".
acceptance::Outcome RunOutcome(const std::vector<acceptance::UnitVerdict>& verdicts);

}  // namespace gyrocal::runreport

namespace gyrocal::runreport {

// The acceptance of a run: limits (given, else stored with the run) and each unit's verdict.
struct RunAcceptance {
    RunLimits limits;
    std::vector<acceptance::UnitVerdict> verdicts;  // empty without limits
};
// `given`: limits handed in by the caller (e.g. gyrocal report --limits FILE) instead of the
// stored ones; `given_origin` says where they came from.
RunAcceptance AcceptRun(const db::RunDetail& detail,
                        const std::optional<acceptance::Limits>& given = {},
                        const std::string& given_origin = "");

// For people: "Acceptance (limits ...): run FAIL" and one line per unit (acceptance::Summary);
// "Acceptance: no limits ..." without limits.
std::string AcceptanceText(const RunAcceptance& acceptance);
nlohmann::json AcceptanceJson(const RunAcceptance& acceptance);

}  // namespace gyrocal::runreport
