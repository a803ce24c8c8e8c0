#include "processors/fit/fit.hpp"

#include <cmath>

#include "lcmtypes/text/names.hpp"
#include "lcmtypes/text/number.hpp"

namespace gyrocal::fit {

namespace {

constexpr text::NameTable<Method, 3> kMethodNames{
    {{Method::kAuto, "auto"}, {Method::kThreePoint, "3point"}, {Method::kWls, "wls"}}};

constexpr text::NameTable<Refusal, 7> kRefusalNames{
    {{Refusal::kNone, "none"},
     {Refusal::kTooFewTemperatures, "too_few_temperatures"},
     {Refusal::kRangeTooNarrow, "range_too_narrow"},
     {Refusal::kNonFiniteInput, "non_finite_input"},
     {Refusal::kBadStandardError, "bad_standard_error"},
     {Refusal::kIllConditioned, "ill_conditioned"},
     {Refusal::kNotApplicable, "not_applicable"}}};

}  // namespace

std::optional<Method> ParseMethod(const std::string& name) {
    return text::ValueOf(kMethodNames, name);
}

const char* ToString(Method m) { return text::NameOf(kMethodNames, m); }

const char* ToString(Refusal r) { return text::NameOf(kRefusalNames, r); }

std::string FitOptions::Validate() const {
    if (!(min_temp_separation_c >= 0.0) || !std::isfinite(min_temp_separation_c))
        return "--min-temp-separation-c must be a finite number >= 0";
    if (!(min_range_c >= 0.0) || !std::isfinite(min_range_c))
        return "--min-range-c must be a finite number >= 0";
    if (!(same_level_tolerance_c >= 0.0) || !std::isfinite(same_level_tolerance_c))
        return "--same-level-tolerance-c must be a finite number >= 0";
    if (same_level_tolerance_c >= min_temp_separation_c && min_temp_separation_c > 0.0) {
        return text::Printf(
            "--min-temp-separation-c (%g) must exceed --same-level-tolerance-c (%g degC)",
            min_temp_separation_c, same_level_tolerance_c);
    }
    if (max_degree < 1 || max_degree > 3) return "--max-degree must be 1..3";
    if (fixed_degree < 0 || fixed_degree > 3)
        return "--fixed-degree must be 1..3, or 0 to choose on evidence";
    if (!(max_condition_number > 1.0)) return "max condition number must be > 1";
    if (t0_c && !std::isfinite(*t0_c)) return "t0_c must be finite";
    if (pooled_dof < 0 || !std::isfinite(pooled_chi2) || pooled_chi2 < 0.0 ||
        (pooled_dof == 0 && pooled_chi2 != 0.0))
        return "pooled overdispersion must be a finite chi2 >= 0 on dof >= 0 (chi2 0 when dof 0)";
    return "";
}

}  // namespace gyrocal::fit
