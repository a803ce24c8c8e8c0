#include "fit.hpp"

#include <cmath>
#include <cstdio>

namespace gyrocal::fit {

std::optional<Method> ParseMethod(const std::string& text) {
    if (text == "auto") return Method::kAuto;
    if (text == "3point") return Method::kThreePoint;
    if (text == "wls") return Method::kWls;
    return std::nullopt;
}

const char* ToString(Method m) {
    switch (m) {
        case Method::kAuto:
            return "auto";
        case Method::kThreePoint:
            return "3point";
        case Method::kWls:
            return "wls";
    }
    return "?";
}

const char* ToString(Refusal r) {
    switch (r) {
        case Refusal::kNone:
            return "none";
        case Refusal::kTooFewTemperatures:
            return "too_few_temperatures";
        case Refusal::kRangeTooNarrow:
            return "range_too_narrow";
        case Refusal::kNonFiniteInput:
            return "non_finite_input";
        case Refusal::kBadStandardError:
            return "bad_standard_error";
        case Refusal::kIllConditioned:
            return "ill_conditioned";
        case Refusal::kNotApplicable:
            return "not_applicable";
    }
    return "?";
}

std::string FitOptions::Problem() const {
    if (!(min_temp_separation_c >= 0.0) || !std::isfinite(min_temp_separation_c))
        return "--min-temp-separation-c must be a finite number >= 0";
    if (!(min_range_c >= 0.0) || !std::isfinite(min_range_c))
        return "--min-range-c must be a finite number >= 0";
    if (!(same_level_tolerance_c >= 0.0) || !std::isfinite(same_level_tolerance_c))
        return "--same-level-tolerance-c must be a finite number >= 0";
    if (same_level_tolerance_c >= min_temp_separation_c && min_temp_separation_c > 0.0) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "--min-temp-separation-c (%g) must exceed --same-level-tolerance-c (%g degC)",
                      min_temp_separation_c, same_level_tolerance_c);
        return buf;
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
