#pragma once
// What the closed-loop benchmarks share (bench_closed_loop.cpp: the rig in-process;
// bench_closed_loop_othersim.cpp: othersim through the real processes): the PX4-style cubic
// fitted on every still bin, and the held-out figures of a method over seeds and units.
// Header-only (two small benchmark programs).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "processors/analysis/bins.hpp"
#include "processors/model/model.hpp"
#include "tests/bench/procedure/held_out_row.hpp"

namespace gyrocal::bench {

// PX4's temperature calibration (sensors/temperature_compensation): the offset a cubic of the
// temperature, fitted by least squares on every sample at rest of the calibration run; here on
// the still bins of the run (the same data averaged per 10 s, each bin weighing its samples
// equally), dT about mid-range. Its covariance is left 0 (not used by the held-out figures).
// Px4CubicOf: the same fit of any values y[i] [V] at temp_c[i] (the benchmarks also fit the
// calibration data's departure from the truth with it: the fit is linear in y).
inline model::Model Px4CubicOf(const std::vector<double>& temp_c, const std::vector<double>& y_v) {
    model::Model m;
    m.quantity = "offset_v";
    m.term_names = {"1", "dT", "dT^2", "dT^3"};
    m.method = "px4-cubic";
    const auto n = static_cast<Eigen::Index>(temp_c.size());
    double lo = INFINITY, hi = -INFINITY;
    for (const double t : temp_c) lo = std::min(lo, t), hi = std::max(hi, t);
    m.t0_c = 5.0 * std::round(0.5 * (lo + hi) / 5.0);
    Eigen::MatrixXd x(n, 4);
    Eigen::VectorXd y(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        const double d = temp_c[static_cast<size_t>(i)] - m.t0_c;
        x.row(i) << 1.0, d, d * d, d * d * d;
        y[i] = y_v[static_cast<size_t>(i)];
    }
    m.coeffs = x.colPivHouseholderQr().solve(y);
    m.covariance = Eigen::MatrixXd::Zero(4, 4);
    m.temp_min_c = lo;
    m.temp_max_c = hi;
    m.residual_rms = std::sqrt((y - x * m.coeffs).squaredNorm() / std::max<Eigen::Index>(1, n - 4));
    m.n_points = static_cast<int>(n);
    m.condition_number = NAN;
    return m;
}
inline model::Model Px4Cubic(const analysis::BinnedRun& b) {
    std::vector<double> temp_c, gyro_v;
    for (const analysis::Bin& x : b.bins()) temp_c.push_back(x.temp_c), gyro_v.push_back(x.gyro_v);
    return Px4CubicOf(temp_c, gyro_v);
}

// The four methods the closed-loop benchmarks compare, in their rows' order.
inline constexpr const char* kMethods[] = {"plateau set", "final set", "PX4 cubic",
                                           "truth @ T_meas"};

// The table of the methods' totals over every seed and unit, the truth's last: RMS and drift,
// and both over the truth's.
inline void PrintMethodTotals(const std::vector<Row>& total) {
    std::printf("  %-16s %12s %10s %10s %10s\n", "method", "rate RMS", "drift", "RMS/truth",
                "drift/truth");
    for (size_t m = 0; m < 4; ++m)
        std::printf("  %-16s %12.4f %10.2f %10.2f %10.2f\n", kMethods[m], total[m].Rms(),
                    total[m].Drift(), total[m].Rms() / total[3].Rms(),
                    total[m].Drift() / total[3].Drift());
}

}  // namespace gyrocal::bench
