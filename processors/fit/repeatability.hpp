#pragma once
// Repeatability of a unit's offset at a temperature the run visited again.
//
// Points in acquisition order (plateau_id = start time). A point within tolerance_c of an
// earlier point, with at least one point at another temperature between them, is a return; it
// is compared with the latest earlier visit:
//   diff_v      = (y2 - y1) - (f(T2) - f(T1))     f: the fitted offset model, which takes out the
//                                                 small temperature difference between the visits
//   diff_sigma  = sqrt(s1^2 + s2^2)               s: the errors the fit used (window standard
//                                                 error and slow noise; the visits are far apart
//                                                 in time, so their slow noise is independent)
//   in deg/s    : divided by the fitted sensitivity at the level
//   z           = diff / diff_sigma
// |z| <= z_limit (3): repeatable within the errors. Beyond: not repeatable; visits approached from
// opposite sides (one from colder, one from hotter) point at hysteresis, visits from the same side
// at a drift (warm-up, ageing, a disturbance). A disagreement is also seen by the fit (its chi2)
// and, when one visit is far off, by the outlier test.
#include <cstdint>
#include <string>
#include <vector>

#include "processors/fit/fit.hpp"

namespace gyrocal::fit {

struct Repeat {
    double temp_c = 0;  // [degC] mean of the two visits
    int64_t first_id = 0, second_id = 0;
    double first_temp_c = 0, second_temp_c = 0;   // [degC]
    int first_approach = 0, second_approach = 0;  // +1 from colder, -1 from hotter, 0 run start
    double diff_v = 0, diff_sigma_v = 0;          // [V] second - first
    double diff_dps = 0, diff_sigma_dps = 0;      // [deg/s]
    double z = 0;                                 // [1]
    std::string verdict;
};

// offset: the unit's fitted offset model; sensitivity: its sensitivity model (converts to deg/s).
// Both must be usable (model::Validate empty); points need finite values and sigma > 0.
std::vector<Repeat> Repeatability(const std::vector<FitPoint>& points, const model::Model& offset,
                                  const model::Model& sensitivity, double tolerance_c = 2.0,
                                  double z_limit = 3.0);

}  // namespace gyrocal::fit
