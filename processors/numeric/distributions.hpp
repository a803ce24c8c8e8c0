#pragma once
// The few distribution functions the tests of significance need (F, Student t, chi-square,
// normal: the fit's outlier, order and pooling tests, the Allan deviation's intervals), from the
// regularised incomplete beta and gamma functions. Pure numerics.
//
// Quantiles are found by bisection on log x of the tail function (monotone), to a relative 1e-12;
// the tails use the continued fractions of Numerical Recipes' betacf/gcf (modified Lentz). These
// are for thresholds and confidence intervals, where 1e-8 relative accuracy is far more than the
// statistics themselves carry.

namespace gyrocal::numeric {

// P(F > x) for F ~ F(d1, d2); d1, d2 > 0, x >= 0.
double FUpperTail(double x, double d1, double d2);
// The x with P(F(d1, d2) > x) = upper_tail, 0 < upper_tail < 1.
double FUpperQuantile(double upper_tail, double d1, double d2);
// The x with P(|t_nu| > x) = two_sided_tail. nu <= 0 means the normal limit.
double TwoSidedTQuantile(double two_sided_tail, double nu);
// P(chi2_nu <= x), nu > 0, x >= 0.
double ChiSquareLowerTail(double x, double nu);
// The x with P(chi2_nu <= x) = lower_tail, 0 < lower_tail < 1.
double ChiSquareQuantile(double lower_tail, double nu);

}  // namespace gyrocal::numeric
