#pragma once
// A model with named terms and THE evaluator: y = sum_i c_i * term_i(dT, inputs), dT = T - t0_c.
//
// Uncertainty of a value: the model is linear in its coefficients, so with phi the vector of
// term values at the inputs, var(y) = phi' C phi exactly (no gradient or sampling needed); C is
// the coefficient covariance. NaN in C (unknown uncertainty, e.g. a nominal model) gives NaN.
//
// Valid range: a fit is only trusted over [temp_min_c, temp_max_c] (the seed: a narrow range is
// only a guess outside it). Outside it the policy either clips temp_c to the nearest bound before
// evaluating (PX4's choice: the correction stops changing) or extrapolates the polynomial; the
// result says which happened. Which one each consumer uses (one rule, here):
// - compensating samples (gyrocal-compensator, `gyrocal compensate`): their --out-of-range option,
//   default extrapolate, each rate flagged; the firmware header: the policy given at init, clip in
//   its example (the firmware default);
// - a model's value compared with data or truth at a temperature (residuals, leave-one-out
//   predictions, the model's step between revisits, the analysis' bins, stored values, the
//   sequencer's uncertainty): extrapolate, since a clipped value would hide the model's own error;
// - the calibration as applied over a temperature range (curves, tables, the acceptance's change
//   and uncertainty over the range) and a sensitivity used as a scale between V and deg/s: clip,
//   what the firmware applies, and never an extrapolated sensitivity near zero.
#include <Eigen/Dense>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "processors/model/terms.hpp"

namespace gyrocal::model {

inline constexpr const char* kOffsetQuantity = "offset_v";
inline constexpr const char* kSensitivityQuantity = "sensitivity_v_per_dps";

// Thrown for a model that cannot be used; what() names the field and what is valid.
class ModelError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

struct Model {
    std::string quantity;                 // "offset_v" [V] or "sensitivity_v_per_dps" [V/(deg/s)]
    std::vector<std::string> term_names;  // in the order of coeffs
    Eigen::VectorXd coeffs;               // [unit of y / unit of term]
    Eigen::MatrixXd covariance;           // [products of coeff units]; NaN = unknown
    double t0_c = 25.0;                   // [degC] reference of dT
    double temp_min_c = kUnknown;         // [degC] valid range (lowest temperature fitted)
    double temp_max_c = kUnknown;         // [degC]
    double residual_rms = kUnknown;       // [unit of y] weighted residual RMS
    int32_t n_points = 0;                 // [count]
    double condition_number = kUnknown;   // [1] of the scaled design matrix
    std::string method;                   // "3point", "wls", "nominal", "mean", "analysis"
};

enum class RangePolicy { kClip, kExtrapolate };
int CPolicy(RangePolicy policy);  // GYROCAL_CLIP / GYROCAL_EXTRAPOLATE
// Values are those of rate_t.range_flag.
enum class RangeFlag : int8_t { kInRange = 0, kClipped = 1, kExtrapolated = 2 };

std::optional<RangePolicy> ParseRangePolicy(const std::string& text);  // "clip" | "extrapolate"
const char* ToString(RangePolicy policy);

// Empty when usable; otherwise why not (naming the field): sizes consistent, term names known and
// unique, coefficients and t0 finite, range finite and ordered, covariance square (NaN allowed).
std::string Validate(const Model& model);

struct Evaluation {
    double value = kUnknown;     // [unit of y]
    double variance = kUnknown;  // [unit of y ^2] phi' C phi
    RangeFlag range = RangeFlag::kInRange;
};

// A model with its term names resolved once, so evaluation per sample is a few multiplies. The
// value is gyrocal_model.h's gyrocal_eval_policy (the firmware's arithmetic, term by term in
// order); the variance phi' C phi is computed beside it.
class Evaluator {
public:
    // Throws ModelError (with Validate()'s text) when the model is not usable.
    explicit Evaluator(Model model);

    Evaluation Evaluate(const ModelInputs& in, RangePolicy policy) const;
    double Value(const ModelInputs& in, RangePolicy policy) const {
        return Evaluate(in, policy).value;
    }
    // Term values phi at the inputs (temp_c used as given, no range handling): the design row.
    Eigen::VectorXd TermValues(const ModelInputs& in) const;
    bool InRange(double temp_c) const;

    const Model& model() const { return model_; }
    // The model as gyrocal_model.h sees it; points into this Evaluator (valid while it lives and
    // is not moved).
    gyrocal_model_t CView() const;

private:
    Model model_;
    std::vector<ResolvedTerm> terms_;
    std::vector<gyrocal_term_t> c_terms_;
};

// One-off evaluation (resolves the terms each call): for tools and tests; per-sample consumers
// keep an Evaluator. Throws ModelError when the model is not usable.
Evaluation Evaluate(const Model& model, const ModelInputs& in, RangePolicy policy);

// Term values of `terms` at inputs with reference t0_c: the fit's design-matrix row.
// Throws ModelError on an unknown name.
std::vector<ResolvedTerm> ResolveTerms(const std::vector<std::string>& names);
Eigen::VectorXd TermValues(const std::vector<ResolvedTerm>& terms, double t0_c,
                           const ModelInputs& in);

}  // namespace gyrocal::model
