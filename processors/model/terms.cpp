#include "terms.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace gyrocal::model {

namespace {
double Sign(double v) { return std::isfinite(v) ? (v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0)) : kUnknown; }
}  // namespace

const std::vector<TermDef>& AllTerms() {
    // One line per term. Keep names stable: they are stored in every coefficient set.
    static const std::vector<TermDef> kTerms = {
        {"1", false, "1", "constant", [](double, const ModelInputs&, double) { return 1.0; }},
        {"dT", false, "degC", "temp_c - t0_c",
         [](double d, const ModelInputs&, double) { return d; }},
        {"dT^2", false, "degC^2", "(temp_c - t0_c)^2",
         [](double d, const ModelInputs&, double) { return d * d; }},
        {"dT^3", false, "degC^3", "(temp_c - t0_c)^3",
         [](double d, const ModelInputs&, double) { return d * d * d; }},
        {"dTdt", false, "degC/s", "rate of temperature change",
         [](double, const ModelInputs& in, double) { return in.dtemp_dt_c_per_s; }},
        {"heating", false, "1", "+1 on the heating branch, -1 cooling",
         [](double, const ModelInputs& in, double) { return Sign(in.heating); }},
        {"supply", false, "V", "supply_v - 5 V nominal",
         [](double, const ModelInputs& in, double) { return in.supply_v - kNominalSupplyV; }},
        {"direction", false, "1", "+1 / -1 rotation direction",
         [](double, const ModelInputs& in, double) { return Sign(in.direction); }},
        {"warmup", true, "1", "exp(-time_since_power_s / tau_s), written warmup(<tau_s>)",
         [](double, const ModelInputs& in, double tau_s) {
             return std::exp(-in.time_since_power_s / tau_s);
         }},
    };
    return kTerms;
}

bool ResolveTerm(std::string_view name, ResolvedTerm* out, std::string* error) {
    std::string_view base = name;
    std::string_view param_text;
    const auto open = name.find('(');
    if (open != std::string_view::npos) {
        if (name.back() != ')' || open + 2 > name.size() - 1) {
            if (error)
                *error = "term '" + std::string(name) + "' is malformed: write name(<number>)";
            return false;
        }
        base = name.substr(0, open);
        param_text = name.substr(open + 1, name.size() - open - 2);
    }
    for (const TermDef& def : AllTerms()) {
        if (def.name != base) continue;
        if (def.has_param != !param_text.empty()) {
            if (error)
                *error =
                    "term '" + std::string(name) + "': '" + std::string(def.name) +
                    (def.has_param ? "' needs a parameter, e.g. " + std::string(def.name) + "(600)"
                                   : "' takes no parameter");
            return false;
        }
        double param = 0.0;
        if (def.has_param) {
            const std::string text(param_text);
            char* end = nullptr;
            param = std::strtod(text.c_str(), &end);
            if (end != text.c_str() + text.size() || !std::isfinite(param) || param <= 0.0) {
                if (error)
                    *error = "term '" + std::string(name) + "': parameter '" + text +
                             "' is not a positive finite number";
                return false;
            }
        }
        if (out) *out = ResolvedTerm{&def, param};
        return true;
    }
    if (error)
        *error = "unknown term '" + std::string(name) + "' (known: " + KnownTermNames() + ")";
    return false;
}

std::string KnownTermNames() {
    std::string s;
    for (const TermDef& def : AllTerms()) {
        if (!s.empty()) s += ", ";
        s += std::string(def.name) + (def.has_param ? "(<param>)" : "");
    }
    return s;
}

std::vector<std::string> PolynomialTerms(int degree) {
    static const char* kNames[] = {"1", "dT", "dT^2", "dT^3"};
    if (degree < 0 || degree > 3) throw std::invalid_argument("polynomial degree must be 0..3");
    return std::vector<std::string>(kNames, kNames + degree + 1);
}

}  // namespace gyrocal::model
