#include "processors/fitter/slow_noise.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lcmtypes/text/number.hpp"
#include "processors/noise/allan.hpp"

namespace gyrocal::fitter {

SlowNoise ChooseSlowNoise(double option_dps, double nominal_v_per_dps,
                          const std::map<int64_t, gyrocal::noise_t>& noise,
                          const std::map<int64_t, gyrocal::plateau_t>& plateaus,
                          const std::string& sensor_id) {
    SlowNoise out;
    if (option_dps >= 0.0) {
        out.v = option_dps * nominal_v_per_dps;
        out.source =
            text::Printf("--plateau-slow-noise-dps %.4g deg/s x nominal %.4g V/(deg/s) (given)",
                         option_dps, nominal_v_per_dps);
        return out;
    }
    if (plateaus.empty()) {
        out.source = "none: no plateau yet";
        return out;
    }
    int64_t newest_end = 0, first_start = plateaus.begin()->second.start_utime;
    double window_sum_s = 0;
    for (const auto& [id, p] : plateaus) {
        newest_end = std::max(newest_end, p.end_utime);
        first_start = std::min(first_start, p.start_utime);
        window_sum_s += 1e-6 * static_cast<double>(p.end_utime - p.start_utime);
    }
    auto it = noise.upper_bound(newest_end);
    if (it == noise.begin()) {
        out.source = "none: no NOISE_" + sensor_id +
                     " (Allan deviation) for this unit by its newest plateau; the plateaus' errors "
                     "miss the slow noise (give --plateau-slow-noise-dps)";
        return out;
    }
    const gyrocal::noise_t& n = std::prev(it)->second;
    if (!std::isfinite(n.bias_instability_v)) {
        out.source =
            "none: the Allan deviation in NOISE_" + sensor_id + " has no fit (" + n.fit_note + ")";
        return out;
    }
    const double window_s = window_sum_s / static_cast<double>(plateaus.size());
    const double span_s = 1e-6 * static_cast<double>(newest_end - first_start);
    const double rrw = std::isfinite(n.rrw_v_rts) ? n.rrw_v_rts : 0.0;
    const double var = noise::SlowNoiseVariance(n.bias_instability_v, rrw, window_s, span_s);
    // The estimate's own scatter (predictive, Student-t): the variance ~ B^2 has relative variance
    // (2 se_B / B)^2, i.e. nu = B^2 / (2 se_B^2) equivalent dof, and E[1/chi2_nu * nu] = nu/(nu-2).
    double inflate = 1.0;
    if (std::isfinite(n.bias_instability_stderr_v) && n.bias_instability_v > 0) {
        const double nu = n.bias_instability_v * n.bias_instability_v /
                          (2.0 * n.bias_instability_stderr_v * n.bias_instability_stderr_v);
        inflate = nu > 2.5 ? nu / (nu - 2.0) : 5.0;
    }
    out.v = std::sqrt(var * inflate);
    out.source = text::Printf(
        "Allan deviation of this run (NOISE_%s at %lld: B %.3g +- %.2g mV, K %.3g "
        "mV/sqrt(s), %.0f s still in %d segments) for %.0f s windows over a %.0f s span, "
        "variance x%.3g for the estimate's own scatter",
        sensor_id.c_str(), static_cast<long long>(n.utime), 1e3 * n.bias_instability_v,
        1e3 * n.bias_instability_stderr_v, 1e3 * rrw, n.still_s, n.n_segments, window_s, span_s,
        inflate);
    return out;
}

}  // namespace gyrocal::fitter
