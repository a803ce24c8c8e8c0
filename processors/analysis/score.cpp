#include "score.hpp"

#include <algorithm>
#include <cmath>

#include "regress.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

StepScore Score(const Context& c, const MatrixXd& x, double base_cv, const Candidate& cand,
                const AnalysisOptions& o, const VectorXd* noise, int noise_params) {
    StepScore s;
    const Index p = x.cols();
    MatrixXd xe(x.rows(), p + 1);
    xe.leftCols(p) = x;
    s.term = cand.term;
    if (cand.search_tau) {
        // 1-D search of tau on a log grid (ratio ~1.2 between points): the residual sum of squares
        // is smooth in log(tau), and 25 fits of a few hundred bins cost nothing.
        // tau is capped at a tenth of the still data's span: a slower "transient" cannot be told
        // from the sensor's own slow drift (bias instability, rate random walk) in one power cycle.
        const double span_s = (c.bins->back().mid_utime - c.bins->front().mid_utime) * 1e-6;
        const double tau_max = std::min(o.warmup_tau_max_s, o.warmup_max_tau_fraction * span_s);
        if (!(tau_max > o.warmup_tau_min_s)) return s;
        double best_rss = INFINITY;
        const int n_grid = 25;
        for (int k = 0; k < n_grid; ++k) {
            const double tau =
                o.warmup_tau_min_s * std::pow(tau_max / o.warmup_tau_min_s, k / double(n_grid - 1));
            const std::string term = WarmupTerm(tau);
            xe.col(p) = Column(term, c.t0, *c.bins, c.first_utime);
            const LsFit f = FitLs(xe, c.y, c.segment, 0);
            if (f.ok && f.rss < best_rss) {
                best_rss = f.rss;
                s.term = term;
            }
        }
        if (!std::isfinite(best_rss)) return s;
    }
    s.column = Column(s.term, c.t0, *c.bins, c.first_utime);
    xe.col(p) = s.column;
    const LsFit f = FitLs(xe, c.y, c.segment, c.hac_lag, noise, noise_params);
    if (!f.ok) return s;
    s.coef = f.coeffs[p];
    s.var = f.covariance(p, p);
    s.rss = f.rss;
    {
        const VectorXd sc = x.colwise().norm().cwiseMax(1e-300);
        const MatrixXd xs = x * sc.cwiseInverse().asDiagonal();
        const VectorXd proj = s.column - xs * xs.colPivHouseholderQr().solve(s.column);
        s.effect_rms_v =
            std::fabs(s.coef) * proj.norm() / std::sqrt(static_cast<double>(proj.size()));
    }
    s.z2 = s.coef * s.coef / s.var;
    const double cv = BlockedCvMse(xe, c.y, c.cv_blocks, c.cv_guard);
    if (!std::isfinite(cv) || !(base_cv > 0.0)) return s;
    s.cv_gain = (base_cv - cv) / base_cv;
    s.ok = true;
    return s;
}

}  // namespace gyrocal::analysis::detail
