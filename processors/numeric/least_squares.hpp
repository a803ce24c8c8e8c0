#pragma once
// The project's one (weighted) linear least-squares solver. The fitter's weighted fit of plateau
// points (fit/wls.cpp), the analysis' fit of still bins (analysis/regress.cpp, with its
// autocorrelation-robust covariance on top) and the noise terms' fit to the Allan variance
// (noise/allan.cpp) all solve through it.
//
// Solve min_c || W^(1/2) (y - X c) ||^2, W = diag(1 / sigma_i^2) when sigma is given, else I:
//   1. whiten the rows: X_w = diag(1/sigma) X, y_w = y / sigma;
//   2. scale the columns to unit norm, X_s = X_w diag(1/s), s_j = ||X_w col j||, so that the
//      condition number and the rank decision measure the geometry of the data, not the units
//      of the terms;
//   3. column-pivoting Householder QR of X_s (X_s P = Q R), never the normal equations;
//   4. c = diag(1/s) QR.solve(y_w);
//   5. (X'WX)^-1 = diag(1/s) P R^-1 R^-T P' diag(1/s), R^-1 from a triangular solve: never an
//      explicit inverse of X'WX. Symmetrised exactly (consumers test symmetry).
// Refusals (ok = false, `why` says which and why): fewer rows than columns, a column that is zero
// or not finite, numerical rank below the column count, or the smallest |R_jj| / largest below
// min_diag_ratio. The condition number of X_s (2-norm, SVD) only when asked: it costs an SVD.
//
// The pooled noise estimate: ResidualVariance = rss / (n - p), the unbiased variance of
// homoscedastic (or, with sigma, of unit-variance whitened) residuals: the "s^2" of the
// classical covariance s^2 (X'X)^-1.
//
// Leverage: the mean over rows of x'(X'WX)^-1 x for rows NOT in the fit (prediction variance
// per unit noise variance), via the same factorisation.
#include <Eigen/Dense>
#include <string>

namespace gyrocal::numeric {

// The QR's rank decision: smallest / largest |R_jj| of the scaled design at or below this, a
// column is numerically a combination of the others. Not a condition-number limit (the fit
// sets min_diag_ratio to 0 and refuses by condition number, fit.hpp): 1e-10 leaves a margin of
// about 6 decades above double's epsilon (2.2e-16) for the rounding of the factorisation.
inline constexpr double kMinRDiagonalRatio = 1e-10;

struct LeastSquaresOptions {
    double min_diag_ratio = kMinRDiagonalRatio;  // smallest / largest |R_jj| of the scaled design
    bool want_condition_number = false;
};

struct LeastSquares {
    bool ok = false;
    std::string why;            // when !ok
    Eigen::VectorXd coeffs;     // [unit of y / unit of column j]
    Eigen::MatrixXd xtwx_inv;   // (X'WX)^-1: the covariance when sigma is the true noise
    Eigen::VectorXd residuals;  // y - X c (not whitened)
    double rss = 0.0;           // sum of the WHITENED squared residuals (chi2 with sigma)
    int rank = 0;
    int bad_column = -1;          // a column that is zero or not finite at every row (!ok)
    double condition_number = 0;  // of the scaled design; 0 when not asked for (kept on refusals)
};

// sigma: per-row standard errors (> 0, finite), or nullptr for ordinary least squares. Never
// throws on data; throws std::invalid_argument when sigma's size differs from y's or x's rows.
LeastSquares SolveLeastSquares(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                               const Eigen::VectorXd* sigma = nullptr,
                               const LeastSquaresOptions& options = {});

// rss / (n - p); NaN when n <= p.
double ResidualVariance(double rss, Eigen::Index n, Eigen::Index p);

// 2-norm condition number of `m` (ratio of its extreme singular values, by SVD); infinity when
// `m` has no columns or is rank-deficient (smallest singular value 0).
double ConditionNumber(const Eigen::MatrixXd& m);

// Mean over the rows of x_other of x'(X'X)^-1 x, X = x_fit (unweighted, scaled columns, the same
// QR as above); NaN when x_fit cannot be solved or x_other is empty.
double MeanLeverage(const Eigen::MatrixXd& x_fit, const Eigen::MatrixXd& x_other);

// The part of each column of `a` orthogonal to the columns of `base` (least-squares residual
// of a on base, columns of base scaled to unit norm first).
Eigen::MatrixXd ProjectOut(const Eigen::MatrixXd& base, const Eigen::MatrixXd& a);

// Orthonormal basis of x's column space: the thin Q of a column-pivoting QR, rank columns (a
// column that adds nothing is left out, not an error); no columns when x has none.
Eigen::MatrixXd OrthonormalBasis(const Eigen::MatrixXd& x);

}  // namespace gyrocal::numeric
