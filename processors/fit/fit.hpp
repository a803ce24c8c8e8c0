#pragma once
// Fitting a model y(T) to calibration points (plateau offsets or rotation sensitivities).
//
// Seed 3-point ("3point"): with points (T0,V0), (T1,V1), (T2,V2), T0 the FIRST point's temperature
// (also the model's t0_c), solve the seed's equations exactly as written,
//     V1 = V0 + a (T1-T0) + b (T1-T0)^2,   V2 = V0 + a (T2-T0) + b (T2-T0)^2,
// a 2x2 linear system (QR), giving the model {1: V0, dT: a, dT^2: b}. Its covariance propagates
// the points' standard errors through the same (exact, square) linear map.
//
// Weighted least squares ("wls"): minimise chi2 = sum ((y_i - phi_i'c) / sigma_i)^2. Rows are
// whitened by 1/sigma_i and columns scaled to unit norm before a column-pivoting Householder QR
// (never the normal equations, never an explicit inverse of them); the condition number is that
// of the scaled matrix. Covariance = (A'WA)^-1 from the triangular factor, NOT scaled by chi2/dof:
// the sigmas are measured standard errors, so the covariance they imply is the honest one when the
// model is right, and chi2/dof is reported beside it; when chi2/dof exceeds its 3-sigma band
// (1 + 3 sqrt(2/dof)) the result says the scatter exceeds the stated errors (model too small or
// errors understated) instead of silently inflating the covariance.
// Reference T0 for wls: the midpoint of the temperature range rounded to a multiple of 5 degC:
// centring makes the 1, dT, dT^2 columns close to orthogonal (small condition number, small
// coefficient correlations) and a round T0 reads as "offset at 25 degC" across runs.
//
// Order selection (polynomial degree 1..3): Akaike's criterion with KNOWN variances,
// AIC = chi2 + 2 p (p = number of terms; with known sigmas this is Mallows' Cp up to a constant;
// AICc's small-sample term corrects for an ESTIMATED variance, which we do not have, and would
// forbid the quadratic with 4 points). Between nested models that differ by one term, when the
// smaller is true, chi2 drops by a chi2(1) variable (mean 1, sd 1.4); so AIC values within 2 of
// the best are a tie, and a tie goes to the seed's quadratic when it is among them, else to the
// lowest degree. Consequence: AIC(quadratic) - AIC(linear) = 2 - (chi2 drop) <= 2, so a linear
// model is chosen only when the data cannot carry a quadratic (the seed's model is the default);
// the criterion really decides between the quadratic and the cubic, which a quadratic truth
// passes with probability P(chi2_1 < 4) = 0.954.
// Capacity: degree <= levels-1 (a polynomial of degree d needs d+1 distinct temperatures) and
// terms <= points-1 (at least one degree of freedom to check the fit).
// Temperature uncertainty is not in the weights: a plateau's temp_sem (~1e-3 degC) times the
// offset slope (~6e-4 V/degC) is ~1e-6 V, an order below a typical gyro_sem_v (2e-5..4e-5 V).
//
// Refusals (FitResult::refusal, never magic ints): fewer than 3 distinct temperatures; two
// temperatures closer than min_temp_separation_c; range narrower than min_range_c; non-finite
// input; non-positive standard error; ill-conditioned design; degree/method not applicable.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "levels.hpp"
#include "model/model.hpp"

namespace gyrocal::fit {

struct FitPoint {
    model::ModelInputs inputs;  // temp_c required; others as the terms need
    double y = 0.0;             // [unit of y] measured value (plateau mean, sensitivity)
    double sigma_y = 0.0;       // [unit of y] its standard error, > 0
    int64_t id = 0;             // plateau_id / rotation_id
};

enum class Method { kAuto, kThreePoint, kWls };
std::optional<Method> ParseMethod(const std::string& text);  // "auto" | "3point" | "wls"
const char* ToString(Method method);

struct FitOptions {
    Method method = Method::kAuto;       // auto: 3point with exactly 3 points, else wls
    double min_temp_separation_c = 5.0;  // [degC] distinct temperatures closer than this: refuse
    double min_range_c = 20.0;           // [degC] hottest - coldest below this: refuse
    double same_level_tolerance_c =
        1.0;                            // [degC] points this close are one temperature (levels.hpp)
    int max_degree = 3;                 // highest polynomial degree order selection may choose
    int fixed_degree = 0;               // 1..3: use this degree (wls); 0 = choose on evidence
    double max_condition_number = 1e8;  // of the scaled design matrix; above: refuse
    std::optional<double> t0_c;         // [degC] wls reference; default: midpoint rounded to 5
    static FitOptions Defaults() { return {}; }
    // "" when valid, else which option is wrong and its valid range.
    std::string Problem() const;
};

enum class Refusal {
    kNone,
    kTooFewTemperatures,
    kTemperaturesTooClose,
    kRangeTooNarrow,
    kNonFiniteInput,
    kBadStandardError,
    kIllConditioned,
    kNotApplicable,  // the forced method/degree cannot be used on these points
};
const char* ToString(Refusal refusal);

struct DegreeCandidate {
    int degree = 0;
    double chi2 = 0.0;
    double aic = 0.0;  // chi2 + 2 p
};

struct FitResult {
    Refusal refusal = Refusal::kNone;
    std::string detail;  // why refused; or notes on an accepted fit (selection, chi2/dof)
    bool ok() const { return refusal == Refusal::kNone; }

    model::Model model;         // valid when ok()
    Eigen::VectorXd residuals;  // [unit of y] y - fit, per input point
    double chi2 = 0.0;
    int dof = 0;
    double chi2_per_dof = model::kUnknown;  // NaN when dof == 0
    bool scatter_exceeds_errors = false;    // chi2/dof above 1 + 3 sqrt(2/dof)
    std::vector<DegreeCandidate> candidates;
    std::vector<int64_t> used_ids;      // ids of the points used, in input order
    std::vector<double> level_temps_c;  // distinct temperatures found
};

// The seed's method on exactly 3 points (points[0] is the seed's first point, T0).
FitResult SeedThreePoint(const std::vector<FitPoint>& points, const std::string& quantity);

// Weighted least squares of any term list (the analysis adds terms through this).
FitResult FitWls(const std::vector<FitPoint>& points, const std::vector<std::string>& term_names,
                 double t0_c, const std::string& quantity, double max_condition_number = 1e8);

// Refusal checks, method choice and order selection. Points in acquisition order (the first one
// is the seed's T0 for 3point).
FitResult FitPolynomial(const std::vector<FitPoint>& points, const std::string& quantity,
                        const FitOptions& options = FitOptions::Defaults());

// Weighted mean (a one-term "1" model): what a sensitivity can be when its points do not span
// enough temperatures for a temperature model.
FitResult FitWeightedMean(const std::vector<FitPoint>& points, const std::string& quantity);

}  // namespace gyrocal::fit
