#pragma once
// Internal to gyrocal_analysis: the steps of Analyze (analyze.hpp) on the offset side, in the
// files that hold them:
//   offset_step.cpp  steps 4-6: the candidates chosen on the training bins, the warm-up's
//                    localized check, the held-out confirmation, the extended model on all bins
//   displace.cpp     step 8's guards: a named term a time-shaped generic feature mimics or that
//                    the data cannot tell from one; the table-angle confound; edge flags
// Every step can run with nuisance columns (candidates.hpp, Context): the joint search's second
// pass, which accounts for a strong time-shaped feature while the candidates are tested.
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/candidates.hpp"
#include "processors/analysis/evidence.hpp"
#include "processors/analysis/heldout.hpp"
#include "processors/analysis/selection.hpp"

namespace gyrocal::analysis::detail {

std::vector<Eigen::Index> AllRows(size_t n);

// Steps 4 and 5 (and step 8's guard): the terms chosen, checked and confirmed. nuisance_all: on
// all bins, 0 columns for none.
Selection OffsetStep(const BinnedRun& binned, const Split& split, double t0,
                     const AnalysisOptions& o, const Eigen::MatrixXd& nuisance_all,
                     SensorResult& res);

// Step 6: declared and extended models on all bins (nuisance fitted with them, left out of the
// models), the added terms' coefficients and shape parameters with their standard errors.
void FinalModels(const BinnedRun& binned, const std::vector<std::string>& terms, double t0,
                 const AnalysisOptions& o, const Eigen::MatrixXd& nuisance_all, SensorResult& res);

// Step 8's guard against time-shaped mimics (see displace.cpp); returns the effects taken out.
std::vector<std::string> Displace(const Context& train, const BinnedRun& binned, const Split& split,
                                  const Surrogates& s, Selection& sel, const AnalysisOptions& o,
                                  SensorResult& res);

void JointPairFates(Selection& sel, bool confirmed, SensorResult& res);
void AngleConfound(SensorResult& res);
void Edges(const BinnedRun& binned, const AnalysisOptions& o, SensorResult& res);

// The measurement that tells a candidate (effect) from a time-shaped generic feature.
std::string SeparationFromTime(const std::string& effect, const std::string& feature);

// The relative step of a searched parameter's derivative (its standard error, FinalModels): the
// term is evaluated at (1 - step) and (1 + step) times the parameter, so the incremental binner
// tracks those neighbours of every searched dT/dt time constant and branch width too.
constexpr double kParamStepRel = 0.05;
// [degC] the step of a spline knot's position for its standard error (smooth in the knot: the
// derivative of max(0, dT - k)^3 is -3 max(0, dT - k)^2).
constexpr double kKnotStepC = 0.5;

// The number a searched term names: "warmup(312)" -> 312; NaN when it names none.
double ParamOf(const std::string& term);

}  // namespace gyrocal::analysis::detail
