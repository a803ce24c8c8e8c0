#include "processors/rotation/slip_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lcmtypes/text/number.hpp"

namespace gyrocal::rotation {

SlipResult CheckSlip(const SlipInputs& in, double alpha, double min_slip_deg) {
    SlipResult out;
    const size_t n = in.gyro_t_s.size(), m = in.encoder_t_s.size();
    if (n < 2 || m < 3 || !(std::abs(in.sensitivity_v_per_dps) > 0)) return out;
    // G at the gyro's sample times (trapezoid), then at each encoder reading by interpolation.
    std::vector<double> g(n, 0.0);
    for (size_t i = 1; i < n; ++i)
        g[i] = g[i - 1] + 0.5 * (in.gyro_t_s[i] - in.gyro_t_s[i - 1]) *
                              (in.gyro_rate_v[i] + in.gyro_rate_v[i - 1]) /
                              in.sensitivity_v_per_dps;
    std::vector<double> e, w, t;
    for (size_t k = 0; k < m; ++k) {
        const double tk = in.encoder_t_s[k];
        if (tk < in.gyro_t_s.front() || tk > in.gyro_t_s.back()) continue;
        const size_t j = static_cast<size_t>(
            std::upper_bound(in.gyro_t_s.begin(), in.gyro_t_s.end(), tk) - in.gyro_t_s.begin());
        const size_t hi = std::min(j, n - 1), lo = hi == 0 ? 0 : hi - 1;
        const double span = in.gyro_t_s[hi] - in.gyro_t_s[lo];
        const double f = span > 0 ? (tk - in.gyro_t_s[lo]) / span : 0.0;
        const size_t kp = std::min(k + 1, m - 1), km = k == 0 ? 0 : k - 1;
        const double dt = in.encoder_t_s[kp] - in.encoder_t_s[km];
        e.push_back(g[lo] + f * (g[hi] - g[lo]) - in.encoder_deg[k]);
        w.push_back(dt > 0 ? (in.encoder_deg[kp] - in.encoder_deg[km]) / dt : 0.0);
        t.push_back(tk - in.gyro_t_s.front());
    }
    if (e.size() < 3) return out;
    double sew = 0, sww = 0;
    for (size_t k = 0; k < e.size(); ++k) sew += e[k] * w[k], sww += w[k] * w[k];
    out.lag_s = sww > 0 ? -sew / sww : 0.0;
    for (size_t k = 0; k < e.size(); ++k) {
        const double r = std::abs(e[k] + out.lag_s * w[k]);
        if (r > out.max_deviation_deg) out.max_deviation_deg = r, out.at_s = t[k];
    }
    const double window_s = in.gyro_t_s.back() - in.gyro_t_s.front();
    const double s = std::abs(in.sensitivity_v_per_dps);
    const double sigma_t = std::sqrt(std::max(0.0, in.noise_q_v2_s) * window_s) / s;
    const double x = std::sqrt(std::log(2.0 / alpha) / 2.0);
    out.threshold_deg = std::max(
        min_slip_deg, x * sigma_t + 1.5 * window_s * in.offset_stderr_v / s + 2.0 * in.count_deg);
    out.slip = out.max_deviation_deg > out.threshold_deg;
    if (out.slip) {
        out.reason = text::Printf(
            "encoder slip: the gyro's integrated angle departs from the encoder's by "
            "%.3f deg at %.2f s into the move (threshold %.3f deg; lag %.1f ms fitted): the "
            "encoder did not follow the table",
            out.max_deviation_deg, out.at_s, out.threshold_deg, 1e3 * out.lag_s);
    }
    return out;
}

}  // namespace gyrocal::rotation
