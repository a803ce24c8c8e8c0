#pragma once
// How well a coefficient set is known over a temperature range: the early-stop figure of a ramp
// run (ramp_procedure.hpp). At each temperature T of a 1 degC grid over [min_c, max_c], at rest
// and in steady state (model::SteadyStateInputs), the models' own 1-sigma value uncertainty
// sqrt(phi' C phi) (model.hpp) is taken relative to the sensitivity S(T):
//   offset_dps      = max_T sd(offset_v(T)) / |S(T)|          [deg/s]
//   sensitivity_pct = max_T 100 sd(S(T)) / |S(T)|             [%]
// Outside the range the fit saw the polynomial is extrapolated with its covariance, so a set that
// has seen half the range reports the (large) uncertainty of the other half.
#include "processors/model/convert.hpp"
#include "processors/sequencer/procedure.hpp"

namespace gyrocal::sequencer {

// NaN figures when a covariance is unknown (NaN). Throws model::ModelError when a model is not
// usable, std::invalid_argument when min_c > max_c or either is not finite.
CoeffUncertainty UncertaintyOver(const model::CoeffSet& set, double min_c, double max_c);

}  // namespace gyrocal::sequencer
