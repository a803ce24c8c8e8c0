#pragma once
// Internal to gyrocal_analysis: the evidence measured against the run's own noise (analyze.hpp,
// steps 4, 8 and 9).
//   Surrogates     the noise of a model's residual measured (noise_model.hpp: its Allan terms,
//                  the k of the floor bound) and o.surrogates noise vectors like it drawn on the
//                  bins' times from o.surrogate_seed
//   WindowsAbove   the time windows (tiles of 600, 1200 and 2400 s from the first bin) and
//                  temperature bands (8 equal ones) whose residual mean - the model fitted on all
//                  bins - exceeds what the surrogates leave there: each window's statistic
//                  standardised by its mean and spread over the surrogates, the threshold the
//                  (1 - window_fpr) quantile of the surrogates' largest standardised value
//                  (null.hpp, MaxTNull). So "part of the run far from the floor" is judged for a
//                  window of that size, with a stated family-wise false-positive rate. The
//                  statistic (o.window_statistic, analyze.hpp): plugin (the default), |mean|
//                  alone, the surrogates' level taken as exact; studentised, |mean| over the
//                  Allan deviation at the window's tau (WindowSpec::tau_s) of the Allan terms
//                  refitted on the same vector (noise_model.hpp, MeasureAllanTerms), the run and
//                  every surrogate alike, so that the error of the run's estimated noise level
//                  cancels.
//   Surrogates are noise drawn with the Allan deviation the residual shows over its still
//   stretches (noise_model.hpp), not phase-randomised copies of the residual itself: an effect
//   left in the residual (a drift over the whole run) would then be in every surrogate and hide
//   from the very test meant to find it, while over stretches of minutes it barely moves the
//   Allan terms.
#include <Eigen/Dense>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/noise_model.hpp"

namespace gyrocal::analysis::detail {

struct Surrogates {
    NoiseModel model;
    double floor_v = kNan;               // [V] Allan deviation at the bin length of the residual
    std::vector<Eigen::VectorXd> noise;  // on all bins
};

Surrogates MakeSurrogates(const BinnedRun& binned, const Eigen::VectorXd& residual_all,
                          const AnalysisOptions& o);

// x_all: the final model's design on all bins. threshold_out: the standardised threshold.
std::vector<WindowExcess> WindowsAbove(const BinnedRun& binned, const Eigen::MatrixXd& x_all,
                                       const Surrogates& s, const AnalysisOptions& o,
                                       double* threshold_out);

}  // namespace gyrocal::analysis::detail
