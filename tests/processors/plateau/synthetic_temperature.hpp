#pragma once
// Synthetic sensor streams with known truth for the plateau tests: a temperature trace given as a
// function of time, white or AR(1) noise, 100 Hz samples.
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>

#include "processors/plateau/plateau_detector.hpp"
#include "tests/processors/numeric/synthetic_noise.hpp"

namespace gyrocal::plateau::testing {

inline constexpr int64_t kT0Utime = 1'000'000'000'000'000;  // like the rig's start time
inline constexpr double kRateHz = 100.0;

// First-order lag from t_start_s: T = final + (initial - final) exp(-(t - t_start)/tau).
inline double FirstOrderLag(double t_s, double t_start_s, double initial_c, double final_c,
                            double tau_s) {
    if (t_s < t_start_s) return initial_c;
    return final_c + (initial_c - final_c) * std::exp(-(t_s - t_start_s) / tau_s);
}

using numeric::testing::Ar1;

struct StreamSpec {
    std::function<double(double)> temp_true_c;  // truth of the sensor temperature at t [s]
    double temp_noise_c = 0.05;                 // [degC] white
    double gyro_offset_v = 2.5;                 // [V] at 25 degC
    double gyro_drift_v_per_c = 1e-3;           // [V/K]
    double gyro_noise_v = 2e-3;                 // [V] rms
    double gyro_rho = 0.0;                      // AR(1) correlation of gyro noise
    uint64_t seed = 1;
};

class Stream {
public:
    explicit Stream(const StreamSpec& spec)
        : spec_(spec),
          rng_(spec.seed),
          gyro_noise_(spec.gyro_noise_v, spec.gyro_rho, spec.seed + 7) {}
    // The k-th sample (k = 0, 1, ... in order).
    Sample Next() {
        const double t = k_ / kRateHz;
        Sample s;
        s.utime = kT0Utime + static_cast<int64_t>(std::llround(t * 1e6));
        s.seq = k_;
        const double truth = spec_.temp_true_c(t);
        s.temp_c = truth + spec_.temp_noise_c * n_(rng_);
        s.temp_v = 2.5 + 0.009 * (s.temp_c - 25.0);
        s.gyro_v = GyroTruth(truth) + gyro_noise_.Next();
        s.supply_v = 5.0;
        ++k_;
        return s;
    }
    double GyroTruth(double temp_c) const {
        return spec_.gyro_offset_v + spec_.gyro_drift_v_per_c * (temp_c - 25.0);
    }
    static double TimeOf(int64_t utime) { return (utime - kT0Utime) * 1e-6; }

private:
    StreamSpec spec_;
    int64_t k_ = 0;
    std::mt19937_64 rng_;
    std::normal_distribution<double> n_{0.0, 1.0};
    Ar1 gyro_noise_;
};

}  // namespace gyrocal::plateau::testing
