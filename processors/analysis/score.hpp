#pragma once
// Internal to gyrocal_analysis: one candidate's statistics at one selection step (analyze.hpp,
// step 4) on the training rows: (a) z^2 of its coefficient with the autocorrelation-robust
// covariance (optionally with a larger model's residuals as the noise), (b) the relative drop of
// the blocked-CV error, (c) its size after projecting out the model. A shape parameter (dT/dt time
// constant, branch width, warm-up time constant) is found by a 1-D search of its grid first.
#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/candidates.hpp"

namespace gyrocal::analysis::detail {

struct StepScore {
    double z2 = 0.0, cv_gain = 0.0, coef = 0.0, var = 0.0, rss = INFINITY;
    double effect_rms_v = 0.0;  // |coef| * RMS of the regressor after projecting out the model
    std::string term;
    Eigen::VectorXd column;
    bool ok = false;
    bool grid_edge = false;  // the searched parameter ended at an end of its grid
};

// noise / noise_params: see regress.hpp FitLs.
StepScore Score(const Context& c, const Eigen::MatrixXd& x, double base_cv, const Candidate& cand,
                const AnalysisOptions& o, const Eigen::VectorXd* noise = nullptr,
                int noise_params = 0);

}  // namespace gyrocal::analysis::detail
