#pragma once
// What a calibration can publish from one unit's points, and which points it must not use.
//
// Outliers: a leave-one-out test. For each point i the model is fitted to the OTHER points, its
// order chosen on their evidence (FitPolynomial: a point far off can make the fit on all points
// buy a degree to chase it, or miss one the others need); the deleted residual r_i = y_i - yhat_(i)
// has variance c_(i) sigma_i^2 + var(yhat_(i)), where c_(i) = max(1, overdispersion of the fit
// without i, pooled with the other units' evidence as in fit.hpp) scales the point's stated error
// the same way the fit scales its covariance. t_i = r_i / sqrt(that variance) is Student-t with nu
// dof (the dof of that overdispersion estimate; normal when it has none: errors as stated).
// Leaving the point out is what makes the test robust: a point cannot pull the fit (or inflate
// c) toward itself and hide. Threshold: |t_i| > t_nu quantile at two-sided alpha / n
// (Bonferroni over the n points), so a fit of good points loses one by mistake with probability
// at most alpha = family_alpha (0.01) per test. The point with the largest |t_i| / threshold
// beyond 1 is excluded, the order re-chosen on the rest, and the test repeated, up to
// max_fraction of the points (at least one). Single deletion: two points far off together mask
// each other unless other units' evidence pins c (pooling). A point can only be checked when the
// fit of the others keeps at least one dof: the seed's 3-point fit, or a quadratic on four
// points, cannot check, and says so.
//
// Publishable model (a ladder, never nothing while one point exists):
//   complete   FitPolynomial's temperature model (order on evidence, or the forced method) over
//              >= 3 temperatures min_temp_separation_c apart spanning >= min_range_c
//   partial    a straight line when the points offer 2 such temperatures or a narrow range, a
//              weighted mean when they offer 1; with the reason (FitPolynomial's refusal)
// Only non-finite input or a non-positive standard error publishes nothing.
#include <string>
#include <vector>

#include "processors/fit/fit.hpp"

namespace gyrocal::fit {

struct Exclusion {
    int64_t id = 0;
    double temp_c = 0;          // [degC]
    double value = 0;           // [unit of y]
    double residual = 0;        // [unit of y] value - prediction from the other points
    double residual_sigma = 0;  // [unit of y] its standard deviation (see header)
    double statistic = 0;       // [1] residual / residual_sigma
    double threshold = 0;       // [1] |statistic| above this excludes
    std::string reason;
};

struct OutlierOptions {
    bool enabled = true;
    double family_alpha = 0.01;  // [1] chance per fit of excluding a point that is fine
    double max_fraction = 0.25;  // [1] at most this fraction of the points (at least 1)
    static OutlierOptions Defaults() { return {}; }
    std::string Validate() const;  // "" when valid
};

struct CalibrationFit {
    FitResult fit;               // the published model; !fit.ok(): nothing could be fitted
    bool complete = false;       // see header
    std::string partial_reason;  // why not complete; "" when complete
    std::vector<Exclusion> excluded;
    std::string outlier_check;   // what the test concluded, or why it could not run
    std::vector<FitPoint> kept;  // the points the model used
};

CalibrationFit FitCalibration(const std::vector<FitPoint>& points, const std::string& quantity,
                              const FitOptions& options,
                              const OutlierOptions& outliers = OutlierOptions::Defaults());

}  // namespace gyrocal::fit
