#pragma once
// Internal to gyrocal_analysis: what is left after the candidates (analyze.hpp, steps 8-9).
//
// Generic features, built from every channel the bins carry, none of them a candidate:
//   time since start            linear drift / aging                     channel: time
//   slow transient              exp(-t_on/tau), tau from the warm-up search's upper end to 3x
//                               the still span (a warm-up slower than the candidate's grid)
//                                                      channel: time since power-on
//   step                        0 before, 1 after a time searched over the run   channel: time
//   periodic                    sin and cos of 2 pi t / P, P searched on a log grid from 4 bins
//                               to a quarter of the span (4 cycles at least; longer is a trend)
//                                                                                  channel: time
//   temperature^3, ^4           shape in temperature beyond the declared model  (temperature)
//   spline knot, above / below  (T - Tk)^3 above or (Tk - T)^3 below a knot searched over the
//                               middle 60 % of the range: a bend no low polynomial follows
//                                                                               (temperature)
//   dT/dt over 60/300/1200 s    the temperature's rate at other time scales     (temperature)
//   |dT/dt| over 300 s          rate magnitude (direction-free)                 (temperature)
//   supply, supply rate         when every bin has it                           channel: supply
//   air - sensor, x (T - T0)    a thermal gradient the sensor's temperature does not see
//                                          channel: chamber air - sensor temperature
//   air temperature, its rate   chamber air, when every bin has it     channel: chamber air
//   table angle (sin, cos), x (T - T0)   a g-sensitivity through a tilted axis  channel: encoder
//   last turn direction, last turn rate  what the table did before the bin     channel: encoder
// A channel not recorded (or without variation) gives no feature; the result names it and what
// recording would add it.
// Each feature's shape parameter is chosen on the training bins only (by residual sum of
// squares); then the model plus the feature, fitted on the training bins, predicts the held-out
// bins, and the statistic is log(|r0|^2 / |r1|^2) of the held-out residuals without and with it.
// What that statistic reaches by chance is measured, not assumed: the same search and prediction
// run on surrogates of the run's own noise (noise_model.hpp: its Allan deviation), and a feature
// "explains held-out data" when its statistic, standardised by its null, exceeds the
// (1 - feature_fpr) quantile of the surrogates' largest standardised statistic over all features
// (null.hpp, MaxTNull: family-wise false-positive rate feature_fpr), the held-out error drops, and
// its size exceeds min_effect_floor_ratio x the floor (and min_feature_drop of the held-out
// squared residual, 0 by default: an optional practical floor, no longer the test).
// A feature is never added to the model: it is reported ("correlates with"), because nothing
// downstream can evaluate it (the compensators know no run start).
// Diagnostics of the final residual on all bins: lag-1 autocorrelation, trend against time,
// the periodogram's peak, the residual by time window and by temperature band.
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/candidates.hpp"
#include "processors/analysis/heldout.hpp"
#include "processors/analysis/null.hpp"

namespace gyrocal::analysis::detail {

struct GenericFeature {
    std::string name, channel, detail;  // detail: the chosen parameter ("tau 1500 s")
    Eigen::MatrixXd columns;            // on all bins (1 or 2 columns)
    bool competes = false;  // may displace a named candidate that mimics it (time-shaped)
    std::string edge = {};  // the searched parameter ended at an end of its range: what it means
};

// "tau at the upper edge of the searched 30-300 s: the true value may be larger"; unit with its
// leading space (" s").
std::string EdgeText(const std::string& param, bool upper, double lo, double hi,
                     const std::string& unit);

// The generic features' families on all bins (a feature without a parameter keeps only its
// columns outside the span of base_all; one left with none is dropped). absent (when given): the
// channels not recorded, or recorded but without variation, and what recording would add them.
std::vector<Family> FeatureFamilies(const BinnedRun& binned, const Context& train,
                                    const Eigen::MatrixXd& base_all, const AnalysisOptions& o,
                                    std::vector<std::string>* absent = nullptr);

// The channel of the named effects' shape checks below.
inline constexpr const char* kNamedEffectChannel = "named effect";

// A specification check of the named effects (in the spirit of Ramsey's RESET): for each added
// effect that is not a static function of the temperature, its fitted contribution's rate of
// change (the right size at the wrong time: a lag or a kernel the term does not have) and the
// contribution times (T - T0) (a coefficient that changes with temperature), each kept only
// outside the span of base_all. m: the extended model whose design is base_all.
std::vector<Family> NamedShapeFamilies(const BinnedRun& binned, const Context& train,
                                       const Eigen::MatrixXd& base_all, const model::Model& m,
                                       const std::vector<AddedEffect>& added);

// Each family's member chosen on the training rows (residual of base_all) as a feature.
std::vector<GenericFeature> GenericFeatures(const BinnedRun& binned, const Context& train,
                                            const Eigen::MatrixXd& base_all,
                                            const AnalysisOptions& o,
                                            std::vector<std::string>* absent = nullptr);

// The step feature's family: 0 before, 1 after a time searched over the middle 90 % of the run
// (time since the first bin [s]).
Family StepFamily(const std::vector<Bin>& bins);

// The bins' gyro_v [V].
Eigen::VectorXd BinValues(const BinnedRun& binned);

// Held-out residual of the model with columns base_all (+ extra_all), fitted on the training
// rows. Empty when it cannot be fitted.
Eigen::VectorXd HeldResidual(const BinnedRun& binned, const Context& train, const Split& split,
                             const Eigen::MatrixXd& base_all, const Eigen::MatrixXd& extra_all);

// Every family judged on the held-out bins against the model base_all, with the null of the
// surrogates (noise vectors on all bins), and correlated with the residual r_all of the final
// model (all bins); those that explain held-out data first (least left). threshold_out: the
// standardised threshold the null gave.
std::vector<FeatureResult> JudgeFeatures(const BinnedRun& binned, const Context& train,
                                         const Split& split, const Eigen::MatrixXd& base_all,
                                         const Eigen::VectorXd& r_all, double floor_v,
                                         const std::vector<Family>& families,
                                         const std::vector<Eigen::VectorXd>& surrogates,
                                         const AnalysisOptions& o, double* threshold_out);

// Diagnostics of residual r (all bins).
ResidualDiagnostics Diagnose(const BinnedRun& binned, const Eigen::VectorXd& r, double floor_v,
                             const AnalysisOptions& o);

}  // namespace gyrocal::analysis::detail
