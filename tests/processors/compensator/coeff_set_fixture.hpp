#pragma once
// The truth of the compensator's tests: a known coefficient set of S01 (offset and sensitivity
// quadratics of ADXRS610-like magnitude, valid -10..60 degC) and gyro samples made from it.
#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <string>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "processors/model/convert.hpp"

namespace gyrocal::testing {

inline constexpr int64_t kCompensatorStartUtime = 1'000'000'000'000'000;

inline model::Model Quadratic(const char* quantity, double c0, double c1, double c2) {
    model::Model m;
    m.quantity = quantity;
    m.term_names = {"1", "dT", "dT^2"};
    m.coeffs = Eigen::Vector3d(c0, c1, c2);
    m.covariance = Eigen::Matrix3d::Identity() * 1e-14;
    m.t0_c = 25.0;
    m.temp_min_c = -10.0;
    m.temp_max_c = 60.0;
    m.n_points = 5;
    m.method = "wls";
    return m;
}

// Set `id` (its coeff_set_id and utime) of S01 in run `run_id`, as the library takes it.
inline model::CoeffSet KnownCoeffSet(int64_t id, const std::string& run_id) {
    model::CoeffSet s;
    s.utime = id;
    s.coeff_set_id = id;
    s.sensor_id = "S01";
    s.run_id = run_id;
    s.source = "fitter";
    s.offset = Quadratic(model::kOffsetQuantity, 2.5, 4e-4, 3e-6);
    s.sensitivity = Quadratic(model::kSensitivityQuantity, 0.006, 6e-7, -1.2e-8);
    s.plateau_ids = {1, 2, 3, 4, 5};
    return s;
}

// The same set as it travels on COEFFS_S01.
inline coeff_set_t KnownSet(int64_t id, const std::string& run_id) {
    return model::ToMsg(KnownCoeffSet(id, run_id));
}

// Sample `seq` of S01 at 100 Hz turning at `rate_dps`: gyro_v from the known set's own models.
inline gyro_sample_t KnownSample(int64_t seq, double temp_c, double rate_dps) {
    const model::CoeffSet cs = model::FromMsg(KnownSet(1, ""));
    model::ModelInputs in;
    in.temp_c = temp_c;
    const model::Evaluator off(cs.offset), sens(cs.sensitivity);
    gyro_sample_t s{};
    s.utime = kCompensatorStartUtime + seq * 10'000;
    s.sensor_id = "S01";
    s.seq = seq;
    s.temp_c = temp_c;
    s.temp_v = 2.5 + 0.009 * (temp_c - 25);
    s.gyro_v = off.Value(in, model::RangePolicy::kExtrapolate) +
               sens.Value(in, model::RangePolicy::kExtrapolate) * rate_dps;
    s.supply_v = NAN;
    s.supply_counts = -1;
    return s;
}

}  // namespace gyrocal::testing
