#pragma once
// Does the encoder follow the table through a move? The sensitivity S = (integral of the gyro's
// rate signal) / (encoder angle) is only as good as the angle; an encoder whose disk slips on its
// shaft reads less than the table turned, and S comes out too high with nothing in the numbers
// to say so. The gyro itself is the witness: through the move its integrated angle
// G(t) = (1/S) integral_a^t (v - offset) dt must follow the encoder's theta(t) - theta(a) up to
// noise and a small lag, whatever S is (G(b) = theta(b) by construction).
//
// Statistic: e_k = G(t_k) - theta_k at each encoder reading k inside the move's window; the gyro's
// output lags the motion (its low-pass, a few ms), e_k ~ -delta * omega_k with omega the encoder's
// rate, so delta is fitted (least squares) and r_k = e_k + delta omega_k. A slip of s degrees puts
// a step of s into theta that G does not have: max |r_k| reaches about s / 2 or more.
// Threshold: with white rate noise of two-sided level q [V^2 s], G - theta pinned at both ends is a
// Brownian bridge of sigma_T = sqrt(q T) / S over the window T; P(max |bridge| > x sigma_T) <=
// 2 exp(-2 x^2), so x = sqrt(ln(2 / alpha) / 2) keeps false alarms below alpha per move (2.23 for
// alpha 1e-4). Added in full: the offset's error (its line can be off by 3 standard errors, which
// bends G by at most half of T * 3 se / S after the pinning) and two encoder counts. A slip is
// reported only above min_slip_deg as well (a physical size worth a rejection).
#include <string>
#include <vector>

namespace gyrocal::rotation {

struct SlipInputs {
    std::vector<double> gyro_t_s;      // [s] sample times inside the window, increasing
    std::vector<double> gyro_rate_v;   // [V] gyro_v - offset line at those times
    std::vector<double> encoder_t_s;   // [s] encoder reading times inside the window
    std::vector<double> encoder_deg;   // [deg] angle moved since the window's start
    double sensitivity_v_per_dps = 0;  // [V/(deg/s)] the move's own S
    double noise_q_v2_s = 0;           // [V^2 s] two-sided level of the gyro's noise
    double offset_stderr_v = 0;        // [V]
    double count_deg = 0;              // [deg] one encoder count
};

struct SlipResult {
    bool slip = false;
    double max_deviation_deg = 0;  // [deg] max |r_k|
    double at_s = 0;               // [s] from the window's start
    double threshold_deg = 0;      // [deg]
    double lag_s = 0;              // [s] fitted delta
    std::string reason;            // when slip
};

// alpha: false alarms per move; min_slip_deg: smaller deviations are never a slip.
SlipResult CheckSlip(const SlipInputs& in, double alpha, double min_slip_deg);

}  // namespace gyrocal::rotation
