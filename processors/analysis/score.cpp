#include "processors/analysis/score.hpp"

#include <algorithm>
#include <cmath>

#include "processors/analysis/regress.hpp"
#include "processors/numeric/least_squares.hpp"

namespace gyrocal::analysis::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

StepScore Score(const Context& c, const MatrixXd& x, double base_cv, const Candidate& cand,
                const AnalysisOptions&, const VectorXd* noise, int noise_params) {
    StepScore s;
    const Index p = x.cols();
    MatrixXd xe(x.rows(), p + 1);
    xe.leftCols(p) = x;
    s.term = cand.grid.front();
    if (cand.grid.size() > 1) {
        // 1-D search of the shape parameter on its grid by residual sum of squares (smooth in
        // the log of the parameter; a few dozen fits of a few hundred bins cost nothing).
        double best_rss = INFINITY;
        for (const std::string& term : cand.grid) {
            xe.col(p) = c.Column(term);
            if (!xe.col(p).allFinite()) continue;
            const LsFit f = FitLs(xe, c.y, c.segment, 0);
            if (f.ok && f.rss < best_rss) {
                best_rss = f.rss;
                s.term = term;
            }
        }
        if (!std::isfinite(best_rss)) return s;
        s.grid_edge = s.term == cand.grid.front() || s.term == cand.grid.back();
    }
    s.column = c.Column(s.term);
    if (!s.column.allFinite()) return s;
    xe.col(p) = s.column;
    const LsFit f = FitLs(xe, c.y, c.segment, c.hac_lag, noise, noise_params);
    if (!f.ok) return s;
    s.coef = f.coeffs[p];
    s.var = f.covariance(p, p);
    s.rss = f.rss;
    {
        const VectorXd proj = numeric::ProjectOut(x, s.column);
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
