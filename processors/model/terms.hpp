#pragma once
// Named model terms: the registry every model refers to by name.
//
// A model is y = sum_i c_i * term_i(inputs), with dT = temp_c - t0_c. A term is a name, the
// unit of its value and a function of (dT, inputs); some take one numeric parameter written
// in the name, e.g. "warmup(600)" = exp(-time_since_power_s / 600). Adding a term is one line
// in terms.cpp. A term whose input is unknown (NaN) evaluates to NaN, so a model that needs a
// quantity the data lacks yields NaN rather than a silently wrong number.
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace gyrocal::model {

inline constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

// Supply-voltage terms are taken about this nominal supply (ADXRS61x modules run at 5 V), so the
// "1" coefficient stays the offset at nominal supply and the two columns are not collinear.
inline constexpr double kNominalSupplyV = 5.0;

// What a term may depend on; NaN = not known for this sample/point.
struct ModelInputs {
    double temp_c = kUnknown;              // [degC] sensor temperature
    double dtemp_dt_c_per_s = kUnknown;    // [degC/s] rate of change of temp_c
    double supply_v = kUnknown;            // [V] measured supply
    double heating = kUnknown;             // [1] +1 heating branch, -1 cooling branch
    double direction = kUnknown;           // [1] +1 / -1 rotation direction (sensitivity points)
    double time_since_power_s = kUnknown;  // [s] since the unit was powered
};

using TermFn = double (*)(double dT_c, const ModelInputs& in, double param);

struct TermDef {
    std::string_view name;     // exact name, or the part before "(" for a parametric term
    bool has_param;            // name written as "name(<number>)"
    std::string_view unit;     // unit of the term value
    std::string_view meaning;  // one line for --help and error messages
    TermFn fn;
};

// A name resolved against the registry: what the evaluator calls per sample.
struct ResolvedTerm {
    const TermDef* def = nullptr;
    double param = 0.0;
    double operator()(double dT_c, const ModelInputs& in) const { return def->fn(dT_c, in, param); }
};

const std::vector<TermDef>& AllTerms();

// Resolves "dT^2", "warmup(600)" ...; nullopt-like failure is reported by the bool and `error`
// (what was wrong and the known names), so callers can build their own context.
bool ResolveTerm(std::string_view name, ResolvedTerm* out, std::string* error);

// "1, dT, dT^2, ..." for error messages.
std::string KnownTermNames();

// The polynomial term names of degree 0..degree: {"1","dT","dT^2",...}; degree <= 3.
std::vector<std::string> PolynomialTerms(int degree);

}  // namespace gyrocal::model
