#pragma once
// The Allan deviation of a unit as a figure (plot::Figure, drawn by the one gnuplot path):
// log-log, the measured points with their 68 % intervals, the fitted
// sigma_A(tau) = sqrt(N^2/tau + B^2 + K^2 tau/3), and its three asymptotes with their slopes
// marked: N/sqrt(tau) (-1/2, angle random walk), B (0, bias instability), K sqrt(tau/3) (+1/2,
// rate random walk); a term not fitted (0 or NaN) has no asymptote. Figure name <id>_allan.
#include <optional>
#include <string>
#include <vector>

#include "processors/plot/figure.hpp"

namespace gyrocal::noise {

struct AllanPlotInput {
    std::string sensor_id;
    std::vector<double> tau_s, adev_v, adev_lo_v, adev_hi_v;
    double arw_v_rthz = 0, bias_v = 0, rrw_v_rts = 0;  // fitted terms (NaN/0 = not fitted)
    std::optional<double> sensitivity_v_per_dps;       // converts to deg/s when given
};

plot::Figure MakeAllanPlot(const AllanPlotInput& in);

}  // namespace gyrocal::noise
