#pragma once
// Sensitivity of ONE gyro from encoder-measured rotations: the seed's indirect method,
//     S = (1/angle) * integral (V_gyro - V_offset) dt,   angle from the encoder.
//
// Per move (motion::TableMove from the shared encoder's MoveDetector; start = last reading at
// rest, end = last change):
//   integration window   [a, b] = [start - guard_s, end + guard_s]   (catches the whole motion
//                        although the detector sees it only after a few counts)
//   rest before          [max(a - rest_s, previous move's b), a)
//   rest after           (b, min(b + rest_s, next move's a)]
// offset: the two rest means m1, m2 at their mean times t1, t2, joined by a straight line (a
// slow offset drift is then removed to first order; with equal windows this is the mean of both
// rest windows, as the seed does). The integral is the trapezoid rule over the sample
// timestamps of (v_i - offset(t_i)); offset_v reported is the line at the window's centre.
//
// Uncertainty (1 sigma), propagated to S = I/theta:
//   offset:  var_I += (T_int * se_offset)^2, se_offset^2 = w1^2 se1^2 + w2^2 se2^2 with
//            w1, w2 the line's weights at the window centre and se_i^2 = var * tau_int / n_i
//   noise:   var_I += q * T_int, q = var * tau_int * dt the noise's two-sided spectral level
//   where var (about each rest window's line) and the integrated autocorrelation time tau_int
//   are pooled over both rest windows (numeric/series_stats.hpp: effective sample size, since 200
//   samples are too few for batch means); the module's LPF makes samples correlated, and white
//   noise gives tau_int = 1, q = sigma^2 dt.
//   encoder: var_theta = 2 * q_deg^2 / 12 (two readings, each +-half a count)
//   var_S = var_I / theta^2 + S^2 var_theta / theta^2.
// Encoder slip (slip_check.hpp): the encoder's readings through the move must follow the gyro's
// integrated angle; a point whose encoder did not is rejected with "encoder slip: ...".
// A point is published rejected (accepted = false, reject_reason) when: the angle is below
// min_angle_deg; a rest window holds less than min_rest_fraction of rest_s; any sequence gap
// lies between the first rest sample and the last; the move lasted more than max_move_s; fewer
// than 2 samples were integrated; or a result is not finite.
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "processors/motion/gyro_sample.hpp"
#include "processors/motion/table_motion.hpp"

namespace gyrocal::rotation {

struct RotationConfig {
    double guard_s = 0.5;            // [s] between the move and each rest window
    double rest_s = 2.0;             // [s] each rest window
    double min_rest_fraction = 0.8;  // [1] of rest_s a rest window must cover
    double min_angle_deg = 10.0;     // [deg] smaller moves are rejected
    double max_move_s = 120.0;       // [s] longer moves are rejected (and bound the memory)
    double encoder_stale_s = 2.0;    // [s] finish without the encoder once samples are this late
    double slip_alpha = 1e-4;        // [1] false slip alarms per move (slip_check.hpp)
    double min_slip_deg = 0.2;       // [deg] smaller departures are never called a slip
    static RotationConfig Defaults() { return {}; }
    // "" when valid, else a sentence naming the field and its valid range.
    std::string Validate() const;
};

// A gyro sample (the one struct, motion/gyro_sample.hpp); supply_v is not used here.
using Sample = motion::GyroSample;

struct Point {
    int64_t rotation_id = 0;                 // [us] = start_utime
    int64_t start_utime = 0, end_utime = 0;  // [us] integration window [a, b]
    int64_t first_seq = 0, last_seq = 0;
    int32_t n_samples = 0;
    int8_t direction = 0;
    double temp_c = std::numeric_limits<double>::quiet_NaN();
    double encoder_angle_deg = 0;
    double offset_v = std::numeric_limits<double>::quiet_NaN();
    double offset_stderr_v = std::numeric_limits<double>::quiet_NaN();
    double integral_v_s = std::numeric_limits<double>::quiet_NaN();
    double sensitivity_v_per_dps = std::numeric_limits<double>::quiet_NaN();
    double sensitivity_stderr_v_per_dps = std::numeric_limits<double>::quiet_NaN();
    bool accepted = false;
    std::string reject_reason;
};

// What the shared encoder knows now.
struct MotionView {
    std::optional<int64_t> watermark_utime;      // [us] newest encoder reading
    std::optional<int64_t> current_start_utime;  // [us] start of the move under way
};

class RotationEstimator {
public:
    explicit RotationEstimator(const RotationConfig& config);  // throws invalid_argument

    // Every move of the table, in order.
    void AddMove(const motion::TableMove& move);
    // One sample, utime increasing (the caller guards order and finiteness).
    void AddSample(const Sample& s);
    // Every reading of the encoder, in order (for the slip check; without any, it is skipped).
    void AddEncoder(const motion::EncoderReading& reading);
    // Points whose rest window after the move is complete.
    std::vector<Point> Poll(const MotionView& motion);

private:
    struct Pending {
        motion::TableMove move;
        int64_t pre_limit_utime;  // rest before may not start earlier (previous move's b)
    };
    Point Compute(const Pending& p, int64_t post_limit_utime) const;
    void Prune();

    RotationConfig config_;
    int64_t guard_us_, rest_us_;
    std::deque<Sample> samples_;
    std::deque<motion::EncoderReading> encoder_;
    std::deque<Pending> pending_;
    std::optional<int64_t> last_b_utime_;
};

}  // namespace gyrocal::rotation
