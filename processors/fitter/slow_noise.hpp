#pragma once
// Which slow noise the fitter adds to a unit's plateau errors, and where the value came from
// (fitter_core.hpp, "Slow noise").
#include <cstdint>
#include <map>
#include <string>

#include "gyrocal/noise_t.hpp"
#include "gyrocal/plateau_t.hpp"

namespace gyrocal::fitter {

struct SlowNoise {
    double v = 0.0;      // [V] standard deviation added in quadrature to each plateau's error
    std::string source;  // for a person: the option, or the Allan estimate used, or why none
};

// option_dps >= 0: that value times the nominal sensitivity. Otherwise the newest NOISE not later
// than the newest plateau's end: noise::SlowNoiseVariance(B, K, window, span) with the plateaus'
// mean window and their span (first start to last end), times nu / (nu - 2) with
// nu = B^2 / (2 se_B^2) (5 when nu <= 2.5): the variance estimate scatters (chi2-like on nu dof),
// and an honest weight needs E[true / estimated] = 1, not an unbiased variance (Student's
// predictive correction). Measured in the virtual lab: without it, 3-point fits on three quiet
// segments claimed mean z^2 1.59; with it 1.10 (tests/support/virtual_lab_test/allan_z2_test).
// None usable: 0, and why.
SlowNoise ChooseSlowNoise(double option_dps, double nominal_sensitivity_v_per_dps,
                          const std::map<int64_t, gyrocal::noise_t>& noise_by_utime,
                          const std::map<int64_t, gyrocal::plateau_t>& plateaus,
                          const std::string& sensor_id);

}  // namespace gyrocal::fitter
