#pragma once
// Internal to gyrocal_analysis: the declared model and the before/after error figures.
//   PlateauPoints   plateau means usable for the declared offset fit (ended before a time)
//   DeclaredOffset  the declared offset terms by weighted least squares on them (fit::FitWls, T0
//                   mid-range rounded to 5 degC, as the fitter does)
//   BinModel        a model::Model from a least-squares fit on bins (method "analysis")
//   ErrorsOn        offset RMS [V], rate RMS [deg/s] and integrated-angle drift [deg/h] of a model
//                   on held-out bins (analyze.hpp, step 5)
//   ExpectedAfter   what the after figure should be if the extended model is right (analyze.hpp)
#include <optional>
#include <string>
#include <vector>

#include "analyze.hpp"
#include "bins.hpp"
#include "fit/fit.hpp"
#include "regress.hpp"

namespace gyrocal::analysis::detail {

void ErrorsOn(const std::vector<Bin>& hold, const model::Evaluator& offset,
              const std::optional<model::Evaluator>& sens, double period_s, int64_t first_utime,
              ErrorFigures* e);

// Mean of 1 / sensitivity over the bins (at rest; those in a plateau window only when
// plateau_only): converts an offset RMS [V] to a rate RMS [deg/s]. NaN when there is no bin or a
// sensitivity is not finite or zero.
double MeanInverseSensitivity(const model::Evaluator& sens, const std::vector<Bin>& bins,
                              int64_t first_utime, bool plateau_only);

// fit: the extended model on the training bins; x_held: its columns on the held-out bins.
void ExpectedAfter(const LsFit& fit, const Eigen::MatrixXd& x_held, const std::vector<Bin>& held,
                   const std::optional<model::Evaluator>& sens, int64_t first_utime,
                   SensorResult* r);

std::vector<fit::FitPoint> PlateauPoints(const std::vector<PlateauInput>& plateaus,
                                         int64_t before_utime);

// nullopt with `why` when it cannot be fitted.
std::optional<model::Model> DeclaredOffset(const std::vector<fit::FitPoint>& pts,
                                           const AnalysisOptions& o, std::string* why);

model::Model BinModel(const std::vector<std::string>& terms, double t0,
                      const std::vector<Bin>& bins, const LsFit& f);

}  // namespace gyrocal::analysis::detail
