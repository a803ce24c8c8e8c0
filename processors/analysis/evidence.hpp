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

// How the final model should transfer to another run of the same profile if it is exactly
// right (analyze.hpp, SensorResult::transfer_*). For surrogate pairs (a, b) = (j, j + 1): the
// model's coefficients fitted to surrogate a (what the run's noise does to them: white, flicker
// and random walk alike, so the level of the run's slow noise moves the intercept and a slow
// input's coefficient as it does in the data, which the HAC covariance of a single run does not
// see) leave P a on the bins (P the projection on x_all's columns); on another run with the same
// inputs the true model's error is b, the fitted model's b - P a. model_rms: sqrt(mean |P a|^2 /
// n), truth_rms: sqrt(mean |b|^2 / n), ratio sqrt(1 + model^2 / truth^2) (the cross term has
// mean 0: a and b are independent), miss_fraction: the share of pairs with |b - P a| / |b| above
// max_ratio. Per column group (`groups`, e.g. one per added term): without its columns the
// model's part falls to model_without; what it adds is sqrt(model^2 - model_without^2).
struct Transfer {
    double model_rms_v = kNan, truth_rms_v = kNan, ratio = kNan, miss_fraction = kNan;
    std::vector<double> group_adds_v;  // per group, [V]
};
Transfer TransferOnSurrogates(const Eigen::MatrixXd& x_all,
                              const std::vector<Eigen::VectorXd>& noise,
                              const std::vector<std::vector<Eigen::Index>>& groups,
                              double max_ratio);

// The transfer check of the final model (design `base` of `terms` on all bins) into
// res.transfer_*: the columns grouped as the declared terms (and any not among res.added) and one
// group per added effect; the group that adds most is named.
void TransferCheck(const Eigen::MatrixXd& base, const std::vector<std::string>& terms,
                   const std::vector<Eigen::VectorXd>& noise, const AnalysisOptions& o,
                   SensorResult& res);

// x_all: the final model's design on all bins. threshold_out: the standardised threshold.
std::vector<WindowExcess> WindowsAbove(const BinnedRun& binned, const Eigen::MatrixXd& x_all,
                                       const Surrogates& s, const AnalysisOptions& o,
                                       double* threshold_out);

}  // namespace gyrocal::analysis::detail
