#pragma once
// The truth of the fitter's tests: offset and sensitivity quadratics (ADXRS610-like magnitudes)
// and the messages a run of them sends the fitter (run events, plateaus, rotations).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "processors/model/convert.hpp"
#include "tests/lcmtypes/message_builders.hpp"

namespace gyrocal::testing {

inline double OffsetTruthV(double t) { return 2.5 + 4e-4 * (t - 25) + 3e-6 * (t - 25) * (t - 25); }
inline double SensTruth(double t) {
    return 0.006 * (1 + 1e-4 * (t - 25) - 2e-6 * (t - 25) * (t - 25));
}

// A set fitted on the noise-free truth above reproduces it to rounding, -10..60 degC, both models
// (1e-12 V is ~1e4 ulp of 2.5 V: far above rounding in a 3x3 solve, far below any fitting error
// that matters).
inline void ExpectTheTruth(const model::CoeffSet& set) {
    model::Evaluator off(set.offset), sens(set.sensitivity);
    for (double temp = -10; temp <= 60; temp += 7) {
        model::ModelInputs in;
        in.temp_c = temp;
        EXPECT_NEAR(off.Value(in, model::RangePolicy::kExtrapolate), OffsetTruthV(temp), 1e-12)
            << temp;
        EXPECT_NEAR(sens.Value(in, model::RangePolicy::kExtrapolate), SensTruth(temp), 1e-12)
            << temp;
    }
}

inline run_event_t FitterRunEvent(const std::string& run_id, const std::string& what, int64_t utime,
                                  const std::vector<std::string>& sensors) {
    run_event_t e = RunEvent(run_id, what, sensors);
    e.utime = utime;
    return e;
}

// A 60 s plateau of sensor `id` at `temp_c` whose mean is the offset truth (sem 2e-5 V).
inline plateau_t TruthPlateau(const std::string& run_id, const std::string& id, double temp_c,
                              int64_t start_utime) {
    plateau_t p = WindowOf<plateau_t>(id, run_id, start_utime, start_utime + 60'000'000);
    p.n_samples = 6000;
    p.temp_mean_c = temp_c;
    p.gyro_mean_v = OffsetTruthV(temp_c);
    p.gyro_sem_v = 2e-5;
    p.supply_mean_v = NAN;
    p.setpoint_c = temp_c;
    return p;
}

// A 90 deg turn (`dir` +1 or -1) of sensor `id` at `temp_c` measuring the sensitivity truth.
inline sensitivity_point_t TruthRotation(const std::string& run_id, const std::string& id,
                                         double temp_c, int64_t start_utime, int dir,
                                         bool accepted) {
    sensitivity_point_t r =
        WindowOf<sensitivity_point_t>(id, run_id, start_utime, start_utime + 5'000'000);
    r.direction = static_cast<int8_t>(dir);
    r.temp_c = temp_c;
    r.encoder_angle_deg = 90.0 * dir;
    r.sensitivity_v_per_dps = SensTruth(temp_c);
    r.sensitivity_stderr_v_per_dps = 1e-6;
    r.accepted = accepted;
    r.reject_reason = accepted ? "" : "seq gap inside the move";
    return r;
}

}  // namespace gyrocal::testing
