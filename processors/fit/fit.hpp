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
// FitWls itself reports chi2/dof beside it and, when chi2/dof exceeds its 3-sigma band
// (1 + 3 sqrt(2/dof)), says the scatter exceeds the stated errors (model too small or errors
// understated); FitPolynomial then applies the overdispersion (below) and says so.
// Reference T0 for wls: the midpoint of the temperature range rounded to a multiple of 5 degC:
// centring makes the 1, dT, dT^2 columns close to orthogonal (small condition number, small
// coefficient correlations) and a round T0 reads as "offset at 25 degC" across runs.
//
// Order selection (polynomial degree 1..3) with known variances would be Akaike's AIC = chi2 + 2p
// (p = number of terms). But the stated errors are not always the whole noise: a plateau's
// standard error comes from its ~60 s window (batch means) and misses noise slower than the
// window (bias instability at 100-1000 s, rate random walk), so real and simulated plateaus
// scatter ~2x more than their stated errors (chi2/dof 3.5-4.7 on clean data), and AIC then buys
// extra terms to chase that noise (a cubic for 15 of 48 clean units). The usual remedy is
// quasi-likelihood: the errors are understated by a COMMON factor, the overdispersion
//     c = chi2/dof of the reference model = the LARGEST candidate the data can carry
// (it is unbiased whenever any candidate is right), pooled with the same statistic of other fits
// of the same kind when the caller supplies it (FitOptions::pooled_*: the fitter pools the run's
// units, whose plateaus share the window, the chamber and the sensor type), on nu dof in total.
// Selection uses QAIC = chi2 / c' + 2 p with c' = max(1, c): c < 1 is read as noise, not as
// overstated errors (a window's standard error misses slow noise, it does not invent noise).
// Between nested models that differ by one term, when the smaller is true, (chi2 drop)/c is
// F(1, nu) (not chi2(1): c is estimated), so a tie band fixed at 2 would admit an extra term far
// more often than AIC does with known variances (P(F(1,1) > 4) = 0.30 against
// P(chi2_1 > 4) = 0.0455). The small-sample correction therefore widens the tie band to
// F(1, nu)^-1(1 - 0.0455) - 2, which keeps AIC's known-variance error rate (or below it, when
// c < 1 is floored) and tends to 2 as nu grows (nu = 1: 193, 2: 18.5, 4: 6.2, 8: 3.6, 30: 2.4).
// The price is power with few dof: a real but small cubic needs a larger drop (one unit alone on
// five points, nu = 1, almost never shows one; hence the fitter's pooling). AICc's own correction
// 2K(K+1)/(n-K-1) is not used: it corrects for a variance estimated separately inside each model by
// maximum likelihood, and with the five points of a 5-setpoint run it is infinite for the quadratic
// (K = 4 counting c) and forbids the cubic outright, so a real cubic could never be found.
// Without dof to estimate c (the largest candidate has none, and nothing is pooled) the
// behaviour is that of known variances: c' = 1, band 2.
// Ties: QAIC values within the band of the best are a tie, and a tie goes to the seed's quadratic
// when it is among them, else to the lowest degree. Consequence: QAIC(quadratic) - QAIC(linear)
// = 2 - (chi2 drop)/c' <= 2, so a linear model is chosen only when the data cannot carry a
// quadratic (the seed's model is the default); the criterion really decides between the
// quadratic and the cubic, which a quadratic truth passes with probability >= 0.954.
// Covariance of the chosen model: the Birge ratio, scaled by max(1, c) (the same c; reported in
// FitResult::overdispersion and in detail), so that understated errors do not become understated
// coefficient uncertainties; with c estimated on nu dof the normalised coefficient errors are
// Student-t with nu dof (std sqrt(nu/(nu-2)), near 1 only for large nu). A fixed degree uses its
// own chi2/dof (+ pooled) as c for the Birge ratio. The 3-point solution has no dof: unscaled.
// Capacity: degree <= separated levels - 1 (a polynomial of degree d needs d+1 temperatures at
// least min_temp_separation_c apart, levels.hpp: SeparatedLevelCount) and terms <= points-1 (at
// least one degree of freedom to check the fit). Points at close temperatures (a repeated
// setpoint, a return to the start, two setpoints a few degC apart) are kept as data: they add
// weight, and the scatter between them is evidence, but no capacity; they are never a refusal.
// Temperature uncertainty is not in the weights: a plateau's temp_sem (~1e-3 degC) times the
// offset slope (~6e-4 V/degC) is ~1e-6 V, an order below a typical gyro_sem_v (2e-5..4e-5 V).
//
// Refusals (FitResult::refusal, never magic ints): fewer than 3 temperatures min_temp_separation_c
// apart; range narrower than min_range_c; non-finite input; non-positive standard error;
// ill-conditioned design; degree/method not applicable. What can still be published then (a
// lower order, a mean) is calibration_fit.hpp's FitCalibration's business.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "processors/fit/levels.hpp"
#include "processors/model/model.hpp"

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

// Two limits on the condition number of the whitened, column-scaled design, refusing an
// ill-posed fit (Refusal::kIllConditioned). Different values because the solves differ:
// - least squares (FitWls, FitOptions::max_condition_number): the coefficients' sensitivity to
//   the data has a cond^2 * residual term; at 1e8 ~ 1/sqrt(double's epsilon) that term reaches
//   order 1, i.e. the points no longer separate the terms;
// - the seed's 3-point solution (SeedThreePoint) is an exact square solve with no residual, its
//   error grows as cond * epsilon only: 1e12 still leaves about 4 significant digits, so it
//   refuses only temperatures that practically coincide.
inline constexpr double kMaxLeastSquaresConditionNumber = 1e8;
inline constexpr double kMaxThreePointConditionNumber = 1e12;

struct FitOptions {
    Method method = Method::kAuto;       // auto: 3point with exactly 3 points, else wls
    double min_temp_separation_c = 5.0;  // [degC] temperatures closer than this add no capacity
    double min_range_c = 20.0;           // [degC] hottest - coldest below this: refuse
    double same_level_tolerance_c =
        1.0;               // [degC] points this close are one temperature (levels.hpp)
    int max_degree = 3;    // highest polynomial degree order selection may choose
    int fixed_degree = 0;  // 1..3: use this degree (wls); 0 = choose on evidence
    // Of the scaled design matrix (wls); above: refuse.
    double max_condition_number = kMaxLeastSquaresConditionNumber;
    std::optional<double> t0_c;  // [degC] wls reference; default: midpoint rounded to 5
    // Overdispersion evidence from OTHER fits of the same kind (e.g. the run's other units): the
    // sum of their reference models' chi2 and of their dof (FitResult::reference_chi2/_dof),
    // added to this fit's own before c is formed. 0 and 0: this fit's own evidence only.
    double pooled_chi2 = 0.0;
    int pooled_dof = 0;
    static FitOptions Defaults() { return {}; }
    // "" when valid, else which option is wrong and its valid range.
    std::string Validate() const;
};

enum class Refusal {
    kNone,
    kTooFewTemperatures,  // fewer than 3 temperatures min_temp_separation_c apart
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
    double aic = 0.0;  // QAIC = chi2 / max(1, c) + 2 p (= AIC when c is not estimated)
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
    // The overdispersion (see header): c = (reference chi2 + pooled chi2) / (reference dof +
    // pooled dof), NaN when there is no dof to estimate it; the covariance was scaled by
    // covariance_scale = max(1, c) (1 when c is NaN). reference_*: this fit's own reference model
    // (the largest candidate, or the fixed degree), for a caller that pools across fits.
    double overdispersion = model::kUnknown;
    int overdispersion_dof = 0;
    double covariance_scale = 1.0;
    double reference_chi2 = 0.0;
    int reference_dof = 0;
    std::vector<int64_t> used_ids;      // ids of the points used, in input order
    std::vector<double> level_temps_c;  // distinct temperatures found
};

// The seed's method on exactly 3 points (points[0] is the seed's first point, T0).
FitResult SeedThreePoint(const std::vector<FitPoint>& points, const std::string& quantity);

// Weighted least squares of any term list (the analysis tests its sensitivity terms through this;
// its offset terms, on bins, go through numeric/least_squares.hpp directly).
FitResult FitWls(const std::vector<FitPoint>& points, const std::vector<std::string>& term_names,
                 double t0_c, const std::string& quantity,
                 double max_condition_number = kMaxLeastSquaresConditionNumber);

// Refusal checks, method choice and order selection. Points in acquisition order (the first one
// is the seed's T0 for 3point).
FitResult FitPolynomial(const std::vector<FitPoint>& points, const std::string& quantity,
                        const FitOptions& options = FitOptions::Defaults());

// The wls reference temperature: the midpoint of the range rounded to a multiple of 5 degC.
double DefaultT0(double coldest_c, double hottest_c);

// Weighted mean (a one-term "1" model): what a sensitivity can be when its points do not span
// enough temperatures for a temperature model.
FitResult FitWeightedMean(const std::vector<FitPoint>& points, const std::string& quantity);

}  // namespace gyrocal::fit
