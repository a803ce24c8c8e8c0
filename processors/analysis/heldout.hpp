#pragma once
// Internal to gyrocal_analysis: the held-out split and the figures on it (analyze.hpp, steps 2,
// 5 and 7).
//   Split           training and held-out bins: interleaved blocks with a guard between them
//   FitModel        a model::Model from a least-squares fit on bins (method "analysis")
//   ErrorsOn        offset RMS [V], rate RMS [deg/s] and drift [deg/h] of a model on bins
//   HeldOutGain     whether what the added terms predict on the held-out bins is there
//   ExpectedAfter   what the after figure should be if the extended model is right
#include <Eigen/Dense>
#include <optional>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/regress.hpp"

namespace gyrocal::analysis::detail {

struct Split {
    std::vector<Eigen::Index> train, held;  // bin indices, ascending
    std::vector<int> held_block;            // block number of each held bin
    int n_blocks = 0;                       // held-out blocks with at least one bin
};
Split MakeSplit(const std::vector<Bin>& bins, const AnalysisOptions& o);

model::Model FitModel(const std::vector<std::string>& terms, double t0, const BinnedRun& binned,
                      const std::vector<Eigen::Index>& rows, const LsFit& f);

// The model's offset residual y - model on `rows` (its own tracker configuration).
Eigen::VectorXd Residuals(const BinnedRun& binned, const model::Model& offset,
                          const std::vector<Eigen::Index>& rows);

// Mean of 1 / |sensitivity| over the rows at rest: converts [V] to [deg/s]; NaN when not finite.
double MeanInverseSensitivity(const BinnedRun& binned, const model::Model& sens,
                              const std::vector<Eigen::Index>& rows);

// Figures of residuals r (on `rows`, grouped into blocks by `block`): RMS [V]; RMS and drift as
// rates (bin by bin through the sensitivity at the bin); drift = RMS over blocks of
// |integral of the rate error| / block duration [deg/h].
ErrorFigures ErrorsOn(const BinnedRun& binned, const Eigen::VectorXd& r,
                      const std::vector<Eigen::Index>& rows, const std::vector<int>& block,
                      const std::optional<model::Model>& sens);

struct Gain {
    double mean_v2 = kNan;  // [V^2] mean of rb^2 - ra^2: > 0 when the held-out error dropped
    double slope = kNan;    // [1] declared residual regressed on the added terms' prediction
    double z = kNan;        // slope / its standard error
};
// before/after: held-out residuals of the declared and the extended model (both fitted on the
// training bins). The slope's variance is autocorrelation-robust (Newey-West, pairs only within
// one held-out block: blocks are guarded apart), and never below the white-noise value.
Gain HeldOutGain(const Eigen::VectorXd& before, const Eigen::VectorXd& after,
                 const std::vector<int>& block, int hac_lag);

// Diebold-Mariano: the mean over the held-out bins of a^2 - b^2 (a, b: held-out residuals of two
// models fitted on the training bins) over its standard error, autocorrelation-robust as in
// HeldOutGain (Newey-West, pairs only within one held-out block; never below the white value).
// > 0 when b predicts better. NaN when it cannot be computed.
double LossDifferenceZ(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                       const std::vector<int>& block, int hac_lag);

// Mean over the held-out rows of x'(X'X)^-1 x, X the training design (numeric::MeanLeverage, the
// one solver's QR); NaN when X cannot be solved.
double MeanLeverage(const Eigen::MatrixXd& x_train, const Eigen::MatrixXd& x_held);

// fit: the extended model on the training bins; x_held: its columns on the held-out bins.
void ExpectedAfter(const LsFit& fit, const Eigen::MatrixXd& x_held, double inv_sens,
                   SensorResult* r);

}  // namespace gyrocal::analysis::detail
