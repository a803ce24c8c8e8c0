#include "processors/analysis/regress.hpp"

#include <cmath>
#include <limits>

#include "processors/numeric/least_squares.hpp"

namespace gyrocal::analysis {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// The one solver (numeric/least_squares.hpp): unit-norm column scaling, pivoting QR, (X'X)^-1
// from the triangular factor; false when rank-deficient.
bool Solve(const MatrixXd& x, const VectorXd& y, VectorXd* coeffs, MatrixXd* xtx_inv) {
    const numeric::LeastSquares ls = numeric::SolveLeastSquares(x, y);
    if (!ls.ok) return false;
    *coeffs = ls.coeffs;
    if (xtx_inv) *xtx_inv = ls.xtwx_inv;
    return true;
}

}  // namespace

LsFit FitLs(const MatrixXd& x, const VectorXd& y, const std::vector<int>& segment, int hac_lag,
            const VectorXd* noise, int noise_params) {
    LsFit f;
    const Index n = x.rows(), p = x.cols();
    MatrixXd b;
    if (!Solve(x, y, &f.coeffs, &b)) {
        f.why = "design matrix is rank-deficient (" + std::to_string(n) + " bins, " +
                std::to_string(p) + " terms): the data cannot separate the terms";
        return f;
    }
    f.residuals = y - x * f.coeffs;
    f.rss = f.residuals.squaredNorm();
    const VectorXd& e = noise ? *noise : f.residuals;
    const Index noise_p = noise ? std::max<Index>(p, noise_params) : p;
    const double dof = static_cast<double>(n - noise_p);
    // The pooled noise variance s^2 of the classical covariance s^2 (X'X)^-1 (the one solver's).
    const MatrixXd classical = b * numeric::ResidualVariance(e.squaredNorm(), n, noise_p);
    // Meat of the sandwich.
    MatrixXd u = x.array().colwise() * e.array();
    MatrixXd s = u.transpose() * u;
    double c0 = e.squaredNorm(), c1 = 0.0;
    for (int l = 1; l <= hac_lag; ++l) {
        const double w = 1.0 - static_cast<double>(l) / (hac_lag + 1);
        MatrixXd g = MatrixXd::Zero(p, p);
        for (Index t = l; t < n; ++t) {
            if (segment[static_cast<size_t>(t)] != segment[static_cast<size_t>(t - l)]) continue;
            g.noalias() += u.row(t).transpose() * u.row(t - l);
            if (l == 1) c1 += e[t] * e[t - 1];
        }
        s += w * (g + g.transpose());
    }
    if (hac_lag < 1)
        for (Index t = 1; t < n; ++t)
            if (segment[static_cast<size_t>(t)] == segment[static_cast<size_t>(t - 1)])
                c1 += e[t] * e[t - 1];
    f.lag1_autocorr = c0 > 0 ? c1 / c0 : 0.0;
    MatrixXd hac = b * s * b * (dof > 0 ? static_cast<double>(n) / dof : kNan);
    // Never more certain than white noise would make it: per coefficient, the larger variance;
    // the correlations of the HAC matrix are kept and rescaled to those variances.
    f.covariance = hac;
    for (Index i = 0; i < p; ++i)
        for (Index j = 0; j < p; ++j) {
            const double si =
                std::sqrt(std::max(hac(i, i), classical(i, i)) / std::max(hac(i, i), 1e-300));
            const double sj =
                std::sqrt(std::max(hac(j, j), classical(j, j)) / std::max(hac(j, j), 1e-300));
            f.covariance(i, j) = hac(i, j) * si * sj;
        }
    f.ok = f.covariance.allFinite();
    if (!f.ok) f.why = "covariance is not finite (too few bins for the terms)";
    return f;
}

std::pair<int, int> BlockRange(int n, int k, int blocks) {
    const auto begin = static_cast<int>(static_cast<int64_t>(n) * k / blocks);
    const auto end = static_cast<int>(static_cast<int64_t>(n) * (k + 1) / blocks);
    return {begin, end};
}

double BlockedCvMse(const MatrixXd& x, const VectorXd& y, int blocks, int guard) {
    const auto n = static_cast<int>(x.rows());
    double sse = 0.0;
    int count = 0;
    for (int k = 0; k < blocks; ++k) {
        const auto [b0, b1] = BlockRange(n, k, blocks);
        if (b1 <= b0) continue;
        std::vector<Index> train;
        for (int i = 0; i < n; ++i)
            if (i < b0 - guard || i >= b1 + guard) train.push_back(i);
        MatrixXd xt(static_cast<Index>(train.size()), x.cols());
        VectorXd yt(static_cast<Index>(train.size()));
        for (size_t r = 0; r < train.size(); ++r) {
            xt.row(static_cast<Index>(r)) = x.row(train[r]);
            yt[static_cast<Index>(r)] = y[train[r]];
        }
        VectorXd c;
        if (!Solve(xt, yt, &c, nullptr)) return kNan;
        const VectorXd e = y.segment(b0, b1 - b0) - x.middleRows(b0, b1 - b0) * c;
        sse += e.squaredNorm();
        count += b1 - b0;
    }
    return count > 0 ? sse / count : kNan;
}

double ProjectedCorrelation(const MatrixXd& base, const VectorXd& a, const VectorXd& b) {
    MatrixXd ab(a.size(), 2);
    ab << a, b;
    const MatrixXd r = numeric::ProjectOut(base, ab);
    const VectorXd ra = r.col(0), rb = r.col(1);
    const double na = ra.norm(), nb = rb.norm();
    if (!(na > 1e-9 * a.norm()) || !(nb > 1e-9 * b.norm())) return kNan;
    return ra.dot(rb) / (na * nb);
}

}  // namespace gyrocal::analysis
