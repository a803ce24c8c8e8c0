#pragma once
// The ramp the ramp fitter's tests feed (ramp_fitter_test.cpp to the library,
// ramp_fitter_node_test.cpp as messages to the node) and its truth: a unit taken
// 25 -> -15 -> 55 -> 25 degC at 1 degC/min (140 min) with known offset and sensitivity curves and
// white noise (seeded), the table still (one encoder reading per second), a sensitivity point of
// each direction every 300 s.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "processors/model/convert.hpp"
#include "processors/model/inputs.hpp"

namespace gyrocal::testing {

constexpr double kRampNoiseV = 1e-3;   // [V] white noise per sample
constexpr double kRampSensSeV = 5e-6;  // [V/(deg/s)] standard error of a sensitivity point
constexpr double kRampHz = 10.0;       // samples per second (fewer than a rig's, same statistics)

inline double RampOffsetTrue(double t_c) {
    const double d = t_c - 25.0;
    return 2.5 + 5e-4 * d - 3e-6 * d * d;
}
inline double RampSensTrue(double t_c) { return 5e-3 + 2e-6 * (t_c - 25.0); }

struct RampSample {
    int64_t t_us = 0;  // [us] since the start of the ramp
    int64_t seq = 0;   // from 0
    double temp_c = 0, gyro_v = 0;
};
struct RampPoint {
    int64_t rotation_id = 0;  // from 1
    int64_t t_us = 0;         // [us] since the start of the ramp
    double temp_c = 0;
    int direction = 0;  // +1 or -1
    double sensitivity_v_per_dps = 0;
};

// The ramp in time order: on_gyro(RampSample) for each sample, then on_encoder(t_us, count) on
// every second's, on_point(RampPoint) for each direction on every 300 s's, and last
// after_sample(count, t_us), `count` being the samples so far.
template <class OnGyro, class OnEncoder, class OnPoint, class AfterSample>
void FeedRamp(OnGyro on_gyro, OnEncoder on_encoder, OnPoint on_point, AfterSample after_sample) {
    std::mt19937_64 rng(42);
    std::normal_distribution<double> n(0.0, 1.0);
    const double rate = 1.0 / 60.0;
    const double legs[] = {40.0 / rate, 70.0 / rate, 30.0 / rate};
    double t_c = 25.0, t_s = 0.0;
    int64_t seq = 0, rot = 0;
    for (int leg = 0; leg < 3; ++leg) {
        const double dir = leg == 1 ? 1.0 : -1.0;
        for (double s = 0; s < legs[leg]; s += 1.0 / kRampHz, t_s += 1.0 / kRampHz) {
            t_c += dir * rate / kRampHz;
            const int64_t u = static_cast<int64_t>(std::llround(t_s * 1e6));
            on_gyro(RampSample{u, seq++, t_c, RampOffsetTrue(t_c) + kRampNoiseV * n(rng)});
            if (seq % static_cast<int64_t>(kRampHz) == 0) on_encoder(u, seq);
            if (seq % static_cast<int64_t>(300 * kRampHz) == 0) {
                for (int d : {1, -1})
                    on_point(
                        RampPoint{++rot, u, t_c, d, RampSensTrue(t_c) + kRampSensSeV * n(rng)});
            }
            after_sample(seq, u);
        }
    }
}

// A set fitted on the ramp against its truth at steady state, every 5 degC over the range the fit
// saw, within 4 of the fit's own standard uncertainties: with white noise alone the analysis'
// robust covariance is the honest spread of the fit. `max_offset_sigma_v` (when finite): the
// offset's standard uncertainty stays below it (a fit, not the noise of a few samples).
struct RampTruthCheck {
    double max_offset_sigma_v = INFINITY;  // [V]
    bool sensitivity = true;               // the sensitivity curve too
};
inline void ExpectTheRampTruth(const model::CoeffSet& set, const RampTruthCheck& check = {}) {
    for (double t_c = set.offset.temp_min_c; t_c <= set.offset.temp_max_c; t_c += 5.0) {
        const auto off = model::Evaluate(set.offset, model::SteadyStateInputs(set.offset, t_c),
                                         model::RangePolicy::kClip);
        EXPECT_NEAR(off.value, RampOffsetTrue(t_c), 4.0 * std::sqrt(off.variance)) << t_c << " C";
        if (std::isfinite(check.max_offset_sigma_v)) {
            EXPECT_LT(std::sqrt(off.variance), check.max_offset_sigma_v) << "fit, not noise";
        }
        if (!check.sensitivity) continue;
        const auto s =
            model::Evaluate(set.sensitivity, model::SteadyStateInputs(set.sensitivity, t_c),
                            model::RangePolicy::kClip);
        EXPECT_NEAR(s.value, RampSensTrue(t_c), 4.0 * std::sqrt(s.variance)) << t_c << " C";
    }
}

}  // namespace gyrocal::testing
