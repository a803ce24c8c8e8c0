#pragma once
// Least squares on bins with honest uncertainty when residuals are autocorrelated.
//
// Fit: ordinary least squares (bins have equal length, hence about equal noise) through the
// project's one solver (numeric/least_squares.hpp: columns scaled to unit norm, column-pivoting
// Householder QR, (X'X)^-1 from the triangular factor, never an explicit inverse of X'X); this
// file adds what is particular to bins: the autocorrelation-robust covariance and blocked CV.
// Covariance: Newey-West (HAC): B S B with B = (X'X)^-1 and
//   S = sum_t u_t u_t' + sum_{l=1..L} (1 - l/(L+1)) sum_t (u_t u_{t-l}' + u_{t-l} u_t'),
//   u_t = x_t e_t, pairs only inside one segment (contiguous bins),
// times n/(n-p). Per coefficient the reported variance is the larger of HAC's and the classical
// s^2 (X'X)^-1 (HAC's correlations kept), so a noisy HAC estimate can never make a coefficient
// look more certain than white noise would.
// Blocked cross-validation: K contiguous blocks of bins; each block is predicted by a fit on the
// bins outside it and outside a guard of g bins on both sides (so that correlated noise next to
// the block does not leak into its prediction). The figure is the mean squared prediction error.
#include <Eigen/Dense>
#include <string>
#include <vector>

namespace gyrocal::analysis {

struct LsFit {
    bool ok = false;
    std::string why;  // when !ok
    Eigen::VectorXd coeffs;
    Eigen::MatrixXd covariance;  // HAC-or-classical (see above)
    Eigen::VectorXd residuals;
    double rss = 0.0;
    double lag1_autocorr = 0.0;  // of the residuals, within segments
};

// segment[i]: contiguous-run index of row i (rows in time order). hac_lag >= 0 in rows.
// noise: when given, the residuals of a LARGER model (with noise_params columns) stand for the
// noise in the covariance instead of this fit's own residuals: stepwise regression's "error
// variance from the full model", so that an effect not yet in the model does not count as noise
// when another is tested.
LsFit FitLs(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const std::vector<int>& segment,
            int hac_lag, const Eigen::VectorXd* noise = nullptr, int noise_params = 0);

// Rows of block k of K over n rows: [begin, end).
std::pair<int, int> BlockRange(int n, int k, int blocks);

// Mean squared out-of-block prediction error; NaN when some fold cannot be fitted.
double BlockedCvMse(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, int blocks, int guard_rows);

// Correlation of columns a and b after projecting out the columns of `base` (|.| near 1: the data
// cannot tell a from b given the model). NaN when either is (nearly) in the span of base.
double ProjectedCorrelation(const Eigen::MatrixXd& base, const Eigen::VectorXd& a,
                            const Eigen::VectorXd& b);

}  // namespace gyrocal::analysis
