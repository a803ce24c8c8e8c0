#pragma once
// Named model terms: the registry every model refers to by name.
//
// A model is y = sum_i c_i * term_i(inputs), with dT = temp_c - t0_c. A term is a name, the
// unit of its value and a kind of gyrocal_model.h, whose C function computes it: the C++
// libraries and the exported firmware header evaluate every term with the same code. Some terms
// take one numeric parameter written in the name, e.g. "warmup(600)" = exp(-time_since_power_s /
// 600), "heating(2.5)" = the play-operator branch of width 2.5 degC, "dTdt(20)" = dT/dt tracked
// with a 20 s time constant, "dT*dTdt(20)" = dT times that dT/dt. A term whose input is unknown
// (NaN), or was tracked with another time constant or width than its name says, evaluates to NaN,
// so a model that needs a quantity the data lacks yields NaN rather than a silently wrong number.
// The inputs themselves are defined, with their state, in inputs.hpp (the trackers of
// gyrocal_model.h).
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "processors/model/gyrocal_model.h"

namespace gyrocal::model {

inline constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

// Supply-voltage terms are taken about this nominal supply (ADXRS61x modules run at 5 V), so the
// "1" coefficient stays the offset at nominal supply and the two columns are not collinear.
inline constexpr double kNominalSupplyV = GYROCAL_NOMINAL_SUPPLY_V;

// What a term may depend on (gyrocal_inputs_t of gyrocal_model.h); every field NaN = not known
// for this sample/point until set. Filled per sample by model::InputTracker (inputs.hpp).
struct ModelInputs : gyrocal_inputs_t {
    ModelInputs() : gyrocal_inputs_t(gyrocal_inputs_unknown()) {}
    explicit ModelInputs(const gyrocal_inputs_t& in) : gyrocal_inputs_t(in) {}
};

enum class ParamMode { kNone, kRequired, kOptional };

struct TermDef {
    std::string_view name;     // exact name, or the part before "(" for a parametric term
    ParamMode param;           // whether the name carries "(<number>)"
    int kind;                  // GYROCAL_TERM_* of gyrocal_model.h
    std::string_view unit;     // unit of the term value
    std::string_view meaning;  // one line for --help and error messages
    bool any_sign = false;     // the parameter may be zero or negative (a knot relative to t0)
};

// A name resolved against the registry: what the evaluator calls per sample.
struct ResolvedTerm {
    const TermDef* def = nullptr;
    gyrocal_term_t c{GYROCAL_TERM_UNKNOWN, 0.0};  // kind and parameter for gyrocal_model.h
    double operator()(double dT_c, const ModelInputs& in) const {
        return gyrocal_term_value(&c, dT_c, &in);
    }
};

const std::vector<TermDef>& AllTerms();

// Resolves "dT^2", "warmup(600)" ...; failure is reported by the bool and `error` (what was
// wrong and the known names), so callers can build their own context.
bool ResolveTerm(std::string_view name, ResolvedTerm* out, std::string* error);

// "1, dT, dT^2, ..." for error messages.
std::string KnownTermNames();

// The polynomial term names of degree 0..degree: {"1","dT","dT^2",...}; degree <= 3.
std::vector<std::string> PolynomialTerms(int degree);

// Names of parametric terms with their parameter written the one way every producer writes it
// (3 significant digits: a parameter is searched on a grid, more digits would claim precision
// the data do not give).
std::string WarmupTerm(double tau_s);
std::string BranchTerm(double width_c);
std::string RateTerm(double tau_s);
// "dT*dTdt(tau)": dT x dT/dt tracked with the same time constant as RateTerm(tau) (one rate
// tracker per coefficient set, so the two always name the same tau).
std::string LagProductTerm(double tau_s);
// A spline knot k_c degC from t0_c: "knot_above(k)" = max(0, dT - k)^3, "knot_below(k)" =
// max(0, k - dT)^3 (3 significant digits, or 0.1 degC where that is coarser).
std::string KnotAboveTerm(double k_c);
std::string KnotBelowTerm(double k_c);
// The parametric term `base` ("warmup", "dTdt", "dT*dTdt", "heating", "knot_above", "knot_below")
// at another parameter value, written as the functions above write it; std::invalid_argument for
// any other.
std::string ParamTerm(std::string_view base, double param);

}  // namespace gyrocal::model
