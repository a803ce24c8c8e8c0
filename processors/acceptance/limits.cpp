#include "processors/acceptance/limits.hpp"

#include <cmath>
#include <fstream>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

namespace gyrocal::acceptance {

namespace {

using nlohmann::json;

std::string TypeName(const json& v) {
    if (v.is_number_integer() || v.is_number_unsigned()) return "a whole number";
    if (v.is_number()) return "a number";
    return v.type_name();
}

std::string LimitKeys() {
    std::string keys;
    for (const LimitDef& d : LimitDefs()) keys += (keys.empty() ? "" : ", ") + std::string(d.key);
    return keys;
}

std::string ValidKeys() { return "description, " + LimitKeys(); }

double NonNegative(const json& v, const std::string& origin, const std::string& key) {
    if (!v.is_number())
        throw LimitsError(origin + ": key '" + key + "': expected a number >= 0, got " +
                          TypeName(v) + " (" + v.dump() + ")");
    const double x = v.get<double>();
    if (!std::isfinite(x) || x < 0)
        throw LimitsError(origin + ": key '" + key + "': " + v.dump() +
                          " is not valid; expected a number >= 0");
    return x;
}

int Count(const json& v, const std::string& origin, const std::string& key) {
    const bool whole = v.is_number_integer() || v.is_number_unsigned() ||
                       (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>());
    if (!whole)
        throw LimitsError(origin + ": key '" + key + "': expected a whole number >= 1, got " +
                          TypeName(v) + " (" + v.dump() + ")");
    const double x = v.get<double>();
    if (x < 1 || x > 1e6)
        throw LimitsError(origin + ": key '" + key + "': " + v.dump() +
                          " is not valid; expected a whole number from 1 to 1000000");
    return static_cast<int>(x);
}

// The numeric limits by key, each a member of Limits: FromJson reads them, ToJson writes the set
// ones, Empty asks whether any is set (description and no_unexplained_residual are their own).
template <class T>
using LimitField = std::pair<std::string_view, std::optional<T> Limits::*>;

const std::vector<LimitField<double>>& NonNegativeLimits() {
    static const std::vector<LimitField<double>> fields = {
        {"max_residual_rms_over_floor", &Limits::max_residual_rms_over_floor},
        {"max_offset_change_dps", &Limits::max_offset_change_dps},
        {"max_sensitivity_rel_uncertainty_pct", &Limits::max_sensitivity_rel_uncertainty_pct},
        {"max_heldout_rate_rms_dps", &Limits::max_heldout_rate_rms_dps},
        {"max_heldout_drift_dph", &Limits::max_heldout_drift_dph},
    };
    return fields;
}

const std::vector<LimitField<int>>& CountLimits() {
    static const std::vector<LimitField<int>> fields = {
        {"min_plateaus", &Limits::min_plateaus},
        {"min_turns", &Limits::min_turns},
    };
    return fields;
}

// The member of `fields` named `key`, or nullptr.
template <class T>
std::optional<T> Limits::*FieldOf(const std::vector<LimitField<T>>& fields,
                                  const std::string& key) {
    for (const auto& [name, member] : fields)
        if (name == key) return member;
    return nullptr;
}

}  // namespace

bool Limits::Empty() const {
    for (const auto& [key, member] : NonNegativeLimits())
        if (this->*member) return false;
    for (const auto& [key, member] : CountLimits())
        if (this->*member) return false;
    return !no_unexplained_residual;
}

const std::vector<LimitDef>& LimitDefs() {
    static const std::vector<LimitDef> defs = {
        {"max_residual_rms_over_floor", "1", "max",
         "offset residual of the plateau set (plateau means only) at its plateaus, RMS in units of "
         "each plateau's noise floor (its "
         "standard error combined with the plateau slow noise the run declared), corrected for the "
         "fitted terms: "
         "sqrt(chi2/dof), about 1 when the model is right; needs more plateaus than offset terms"},
        {"max_offset_change_dps", "deg/s", "max",
         "largest minus smallest fitted offset over the calibrated temperature range, divided by "
         "the fitted "
         "sensitivity at mid-range"},
        {"max_sensitivity_rel_uncertainty_pct", "%", "max",
         "largest 1-sigma uncertainty of the fitted sensitivity over the calibrated temperature "
         "range (from the "
         "coefficient covariance), relative to the sensitivity; unknown (a fail) for a nominal "
         "sensitivity"},
        {"min_plateaus", "count", "min",
         "plateaus (offset points) the unit's plateau set was fitted on (the final set of a "
         "plateau run is "
         "fitted on every still sample, plateaus included)"},
        {"min_turns", "count", "min",
         "accepted turns (sensitivity points) the unit's calibration was fitted on"},
        {"no_unexplained_residual", "-", "require",
         "the newest analysis of the unit (the calibration's closed loop, or a later gyrocal "
         "analyze) left "
         "nothing above the floor unexplained: outcome adequate, or explained with its terms in a "
         "stored set; "
         "not evaluated while the run has no analysis"},
        {"max_heldout_rate_rms_dps", "deg/s", "max",
         "the final set's error on held-out still data: RMS of the 10 s bins' rate error (the "
         "closed-loop "
         "analysis behind the set, fitted without those bins); not evaluated for a set without one "
         "(a plateau "
         "run without the closed loop: run gyrocal analyze)"},
        {"max_heldout_drift_dph", "deg/h", "max",
         "the final set's integrated rate error over a held-out block divided by its length, RMS "
         "over the "
         "blocks (the same analysis)"},
    };
    return defs;
}

Limits FromJson(const json& j, const std::string& origin) {
    if (!j.is_object())
        throw LimitsError(origin +
                          ": expected a JSON object of limits {\"key\": value, ...}, got " +
                          TypeName(j) + " (valid keys: " + ValidKeys() + ")");
    Limits l;
    for (const auto& [key, v] : j.items()) {
        if (key == "description") {
            if (!v.is_string())
                throw LimitsError(origin + ": key 'description': expected a string, got " +
                                  TypeName(v));
            l.description = v.get<std::string>();
        } else if (const auto number = FieldOf(NonNegativeLimits(), key)) {
            l.*number = NonNegative(v, origin, key);
        } else if (const auto count = FieldOf(CountLimits(), key)) {
            l.*count = Count(v, origin, key);
        } else if (key == "no_unexplained_residual") {
            if (!v.is_boolean())
                throw LimitsError(origin +
                                  ": key 'no_unexplained_residual': expected true or false, got " +
                                  TypeName(v) + " (" + v.dump() + ")");
            l.no_unexplained_residual = v.get<bool>();
        } else {
            throw LimitsError(origin + ": unknown key '" + key + "' (valid keys: " + ValidKeys() +
                              ")");
        }
    }
    if (l.Empty())
        throw LimitsError(origin + ": no limit given (set at least one of: " + LimitKeys() + ")");
    return l;
}

Limits ParseLimits(const std::string& text, const std::string& origin) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::parse_error& e) {
        std::string what = e.what();
        if (const size_t at = what.find("] ");
            what.rfind("[json.exception", 0) == 0 && at != std::string::npos)
            what = what.substr(at + 2);
        throw LimitsError(origin + ": not valid JSON: " + what);
    }
    return FromJson(j, origin);
}

Limits LoadLimitsFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f)
        throw LimitsError(path + ": cannot be read (a JSON file of acceptance limits is expected)");
    const std::string text{std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
    return ParseLimits(text, path);
}

json ToJson(const Limits& l) {
    json j = json::object();
    if (!l.description.empty()) j["description"] = l.description;
    for (const auto& [key, member] : NonNegativeLimits())
        if (l.*member) j[std::string(key)] = *(l.*member);
    for (const auto& [key, member] : CountLimits())
        if (l.*member) j[std::string(key)] = *(l.*member);
    if (l.no_unexplained_residual) j["no_unexplained_residual"] = true;
    return j;
}

}  // namespace gyrocal::acceptance
