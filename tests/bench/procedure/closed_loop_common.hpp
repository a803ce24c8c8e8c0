#pragma once
// What the closed-loop benchmarks share (bench_closed_loop.cpp: the rig in-process;
// bench_closed_loop_othersim.cpp: othersim through the real processes): the PX4-style cubic
// fitted on every still bin, and the held-out figures of a method over seeds and units.
// Header-only (two small benchmark programs).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "analysis/bins.hpp"
#include "model/model.hpp"

namespace gyrocal::bench {

// PX4's temperature calibration (sensors/temperature_compensation): the offset a cubic of the
// temperature, fitted by least squares on every sample at rest of the calibration run; here on
// the still bins of the run (the same data averaged per 10 s, each bin weighing its samples
// equally), dT about mid-range. Its covariance is left 0 (not used by the held-out figures).
inline model::Model Px4Cubic(const analysis::BinnedRun& b) {
    model::Model m;
    m.quantity = "offset_v";
    m.term_names = {"1", "dT", "dT^2", "dT^3"};
    m.method = "px4-cubic";
    const auto n = static_cast<Eigen::Index>(b.size());
    double lo = INFINITY, hi = -INFINITY;
    for (const analysis::Bin& x : b.bins())
        lo = std::min(lo, x.temp_c), hi = std::max(hi, x.temp_c);
    m.t0_c = 5.0 * std::round(0.5 * (lo + hi) / 5.0);
    Eigen::MatrixXd x(n, 4);
    Eigen::VectorXd y(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        const double d = b.bins()[static_cast<size_t>(i)].temp_c - m.t0_c;
        x.row(i) << 1.0, d, d * d, d * d * d;
        y[i] = b.bins()[static_cast<size_t>(i)].gyro_v;
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

// A method's held-out figures over seeds and units: rate RMS of the 10 s bin means over every
// unit, drift = RMS over units of the integrated error / duration.
struct Row {
    std::string label;
    double sum2 = 0, sum2_drift = 0;
    long n = 0;
    int units = 0;
    void Add(const std::vector<double>& err_dps, double angle_deg, double duration_s) {
        for (double e : err_dps)
            if (std::isfinite(e)) sum2 += e * e, ++n;
        const double drift_dph = angle_deg / duration_s * 3600.0;
        sum2_drift += drift_dph * drift_dph;
        ++units;
    }
    double Rms() const { return n > 0 ? std::sqrt(sum2 / n) : NAN; }
    double Drift() const { return units > 0 ? std::sqrt(sum2_drift / units) : NAN; }
};

}  // namespace gyrocal::bench
