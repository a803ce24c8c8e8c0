#pragma once
// Acceptance limits: what a unit's calibration must show to pass, from a small JSON file, e.g.
//
//   {
//     "description": "production limits, ADXRS610 modules",
//     "max_residual_rms_over_floor": 2.0,
//     "max_offset_change_dps": 3.0,
//     "max_sensitivity_rel_uncertainty_pct": 0.5,
//     "min_plateaus": 5,
//     "min_turns": 10,
//     "no_unexplained_residual": true,
//     "max_heldout_rate_rms_dps": 0.05,
//     "max_heldout_drift_dph": 60
//   }
//
// Every key is optional (a limit not given is not checked) but at least one limit must be there.
// The file is read strictly: an unknown key, a value of the wrong type, a negative or non-finite
// limit or a count below 1 is an error naming the key and what would be valid, so a typo never
// becomes a limit silently not applied. The meaning of each limit is in LimitDefs() (also printed
// by docs/report.md and the report).
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace gyrocal::acceptance {

class LimitsError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct Limits {
    std::string description;
    std::optional<double> max_residual_rms_over_floor;          // [1]
    std::optional<double> max_offset_change_dps;                // [deg/s]
    std::optional<double> max_sensitivity_rel_uncertainty_pct;  // [%]
    std::optional<int> min_plateaus;                            // [count]
    std::optional<int> min_turns;                               // [count]
    bool no_unexplained_residual = false;                       // checked when true
    std::optional<double> max_heldout_rate_rms_dps;             // [deg/s] the final set's
    std::optional<double> max_heldout_drift_dph;                // [deg/h] the final set's

    bool Empty() const;
};

// One limit: its key in the file, the unit of its value and what is measured against it.
struct LimitDef {
    std::string_view key;
    std::string_view unit;
    std::string_view kind;     // "max", "min" or "require"
    std::string_view meaning;  // one sentence
};
const std::vector<LimitDef>& LimitDefs();

// Parses and validates the text of a limits file. `origin` (the file name) starts every error.
// Throws LimitsError.
Limits ParseLimits(const std::string& json_text, const std::string& origin);
// Reads and parses a limits file; an unreadable file is a LimitsError naming it.
Limits LoadLimitsFile(const std::string& path);
// The same from parsed JSON (e.g. the copy stored in a run's configuration).
Limits FromJson(const nlohmann::json& j, const std::string& origin);
// Only the keys that are set: FromJson(ToJson(l)) == l.
nlohmann::json ToJson(const Limits& limits);

}  // namespace gyrocal::acceptance
