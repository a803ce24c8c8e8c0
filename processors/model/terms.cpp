#include "processors/model/terms.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "lcmtypes/text/number.hpp"

namespace gyrocal::model {

const std::vector<TermDef>& AllTerms() {
    // One line per term. Keep names stable: they are stored in every coefficient set.
    using P = ParamMode;
    static const std::vector<TermDef> kTerms = {
        {"1", P::kNone, GYROCAL_TERM_ONE, "1", "constant"},
        {"dT", P::kNone, GYROCAL_TERM_DT, "degC", "temp_c - t0_c"},
        {"dT^2", P::kNone, GYROCAL_TERM_DT2, "degC^2", "(temp_c - t0_c)^2"},
        {"dT^3", P::kNone, GYROCAL_TERM_DT3, "degC^3", "(temp_c - t0_c)^3"},
        {"dTdt", P::kOptional, GYROCAL_TERM_DTDT, "degC/s",
         "rate of temperature change, tracked with time constant tau_s (default 5): dTdt(<tau_s>)"},
        {"dT*dTdt", P::kOptional, GYROCAL_TERM_DT_DTDT, "degC^2/s",
         "(temp_c - t0_c) x dTdt(<tau_s>), the same tracker (a thermometer lagging the die on "
         "a curved offset): dT*dTdt(<tau_s>)"},
        {"heating", P::kNone, GYROCAL_TERM_HEATING, "1",
         "+1 / -1 side of the heating/cooling branch last reached (play operator, 1 degC)"},
        {"heating", P::kRequired, GYROCAL_TERM_BRANCH, "1",
         "heating/cooling branch in [-1, 1], play operator of width w_c: heating(<w_c>)"},
        {"supply", P::kNone, GYROCAL_TERM_SUPPLY, "V", "supply_v - 5 V nominal"},
        {"direction", P::kNone, GYROCAL_TERM_DIRECTION, "1", "+1 / -1 rotation direction"},
        {"warmup", P::kRequired, GYROCAL_TERM_WARMUP, "1",
         "exp(-time_since_power_s / tau_s): warmup(<tau_s>)"},
        {"knot_above", P::kRequired, GYROCAL_TERM_KNOT_ABOVE, "degC^3",
         "max(0, dT - k_c)^3: a cubic spline knot k_c degC from t0 (any sign): knot_above(<k_c>)",
         true},
        {"knot_below", P::kRequired, GYROCAL_TERM_KNOT_BELOW, "degC^3",
         "max(0, k_c - dT)^3: a cubic spline knot k_c degC from t0 (any sign): knot_below(<k_c>)",
         true},
    };
    return kTerms;
}

namespace {

bool Fail(std::string* error, std::string text) {
    if (error) *error = std::move(text);
    return false;
}

}  // namespace

bool ResolveTerm(std::string_view name, ResolvedTerm* out, std::string* error) {
    std::string_view base = name;
    std::string_view param_text;
    const auto open = name.find('(');
    if (open != std::string_view::npos) {
        if (name.back() != ')' || open + 2 > name.size() - 1)
            return Fail(error,
                        "term '" + std::string(name) + "' is malformed: write name(<number>)");
        base = name.substr(0, open);
        param_text = name.substr(open + 1, name.size() - open - 2);
    }
    const bool has_param = !param_text.empty();
    bool base_known = false;
    for (const TermDef& def : AllTerms()) {
        if (def.name != base) continue;
        base_known = true;
        if ((def.param == ParamMode::kNone && has_param) ||
            (def.param == ParamMode::kRequired && !has_param))
            continue;  // another entry of the same name may take (or not take) a parameter
        double param = 0.0;
        if (has_param) {
            const std::string text(param_text);
            char* end = nullptr;
            param = std::strtod(text.c_str(), &end);
            const bool bad_sign = !def.any_sign && param <= 0.0;
            if (end != text.c_str() + text.size() || !std::isfinite(param) || bad_sign)
                return Fail(error, "term '" + std::string(name) + "': parameter '" + text +
                                       (def.any_sign ? "' is not a finite number"
                                                     : "' is not a positive finite number"));
        }
        if (out) *out = ResolvedTerm{&def, gyrocal_term_t{def.kind, param}};
        return true;
    }
    if (base_known)
        return Fail(error,
                    "term '" + std::string(name) + "': '" + std::string(base) +
                        (has_param ? "' takes no parameter"
                                   : "' needs a parameter, e.g. " + std::string(base) + "(600)"));
    return Fail(error,
                "unknown term '" + std::string(name) + "' (known: " + KnownTermNames() + ")");
}

std::string KnownTermNames() {
    std::string s;
    for (const TermDef& def : AllTerms()) {
        if (!s.empty()) s += ", ";
        s += std::string(def.name);
        if (def.param == ParamMode::kRequired) s += "(<param>)";
        if (def.param == ParamMode::kOptional) s += "[(<param>)]";
    }
    return s;
}

std::vector<std::string> PolynomialTerms(int degree) {
    static const char* kNames[] = {"1", "dT", "dT^2", "dT^3"};
    if (degree < 0 || degree > 3) throw std::invalid_argument("polynomial degree must be 0..3");
    return std::vector<std::string>(kNames, kNames + degree + 1);
}

namespace {
std::string WithParam(const char* name, double param) {
    return text::Printf("%s(%.3g)", name, param);
}
}  // namespace

std::string WarmupTerm(double tau_s) { return WithParam("warmup", tau_s); }
std::string BranchTerm(double width_c) { return WithParam("heating", width_c); }
std::string RateTerm(double tau_s) { return WithParam("dTdt", tau_s); }
std::string LagProductTerm(double tau_s) { return WithParam("dT*dTdt", tau_s); }

namespace {
// A knot near t0 in 3 significant digits would claim a micro-degree; 0.1 degC is the finest a
// knot searched on a grid over tens of degrees can mean.
std::string KnotParam(const char* name, double k_c) {
    const double k = std::fabs(k_c) < 10.0 ? std::round(k_c * 10.0) / 10.0 : k_c;
    return WithParam(name, k == 0.0 ? 0.0 : k);  // never "-0"
}
}  // namespace

std::string KnotAboveTerm(double k_c) { return KnotParam("knot_above", k_c); }
std::string KnotBelowTerm(double k_c) { return KnotParam("knot_below", k_c); }

std::string ParamTerm(std::string_view base, double param) {
    if (base == "warmup") return WarmupTerm(param);
    if (base == "dTdt") return RateTerm(param);
    if (base == "dT*dTdt") return LagProductTerm(param);
    if (base == "heating") return BranchTerm(param);
    if (base == "knot_above") return KnotAboveTerm(param);
    if (base == "knot_below") return KnotBelowTerm(param);
    throw std::invalid_argument("term '" + std::string(base) + "' takes no searched parameter");
}

}  // namespace gyrocal::model
