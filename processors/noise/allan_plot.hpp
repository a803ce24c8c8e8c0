#pragma once
// The Allan deviation of a unit as a picture (for `gyrocal analyze --plot`), in the style of
// processors/analysis/plot.hpp: data file and gnuplot script as text, the caller writes them into
// one directory and runs gnuplot there. Log-log: the measured points with their 68 % intervals,
// the fitted sigma_A(tau) = sqrt(N^2/tau + B^2 + K^2 tau/3), and its three asymptotes with their
// slopes marked: N/sqrt(tau) (-1/2, angle random walk), B (0, bias instability),
// K sqrt(tau/3) (+1/2, rate random walk). <id>_allan.png and <id>_allan.svg.
#include <optional>
#include <string>
#include <vector>

namespace gyrocal::noise {

struct AllanPlotInput {
    std::string sensor_id;
    std::vector<double> tau_s, adev_v, adev_lo_v, adev_hi_v;
    double arw_v_rthz = 0, bias_v = 0, rrw_v_rts = 0;  // fitted terms (NaN/0 = not fitted)
    std::optional<double> sensitivity_v_per_dps;       // converts to deg/s when given
};

struct AllanPlotFile {
    std::string name, text;
};

struct AllanPlot {
    std::vector<AllanPlotFile> files;  // the .dat and the .gp
    std::vector<std::string> scripts;  // the .gp to run
    std::vector<std::string> images;   // what it writes
};

AllanPlot MakeAllanPlot(const AllanPlotInput& in);

}  // namespace gyrocal::noise
