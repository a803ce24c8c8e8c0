#pragma once
// Helpers shared by the simulator tests: a sink that keeps everything, and the Allan deviation.
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/rig.hpp"

namespace gyrocal::sim::testing {

struct Recorded {
    std::vector<GyroReading> gyro;
    std::vector<GyroTruth> truth;
    std::vector<EncoderReading> encoder;
    std::vector<ChamberReading> chamber;
};

class RecordingSink : public RigSink {
public:
    Recorded data;
    void OnGyro(const GyroReading& r, const GyroTruth& t) override {
        data.gyro.push_back(r);
        data.truth.push_back(t);
    }
    void OnEncoder(const EncoderReading& r) override { data.encoder.push_back(r); }
    void OnChamber(const ChamberReading& r) override { data.chamber.push_back(r); }
};

// A config with everything that could blur a particular test switched to ideal; tests turn on
// what they examine.
inline RigConfig QuietConfig() {
    RigConfig c = RigConfig::Defaults();
    c.num_units = 1;
    c.noise.noise_density_dps_rthz = 0.0;
    c.noise.bias_instability_dps = 0.0;
    c.noise.rate_random_walk_dps_rts = 0.0;
    c.noise.temp_noise_v = 0.0;
    c.thermal.air_noise_c = 0.0;
    c.supply.ripple_v = 0.0;
    c.supply.drift_std_v = 0.0;
    c.supply.noise_v = 0.0;
    c.adc.bits = 0;
    return c;
}

// Overlapping Allan deviation of samples y (spacing dt_s) at cluster size m (tau = m dt).
inline double AllanDeviation(const std::vector<double>& y, double dt_s, size_t m) {
    const size_t n = y.size();
    if (n < 2 * m + 1) return NAN;
    std::vector<double> cum(n + 1, 0.0);
    for (size_t i = 0; i < n; ++i) cum[i + 1] = cum[i] + y[i];
    double sum = 0.0;
    size_t count = 0;
    for (size_t i = 0; i + 2 * m <= n; ++i) {
        const double a = (cum[i + m] - cum[i]) / m;
        const double b = (cum[i + 2 * m] - cum[i + m]) / m;
        sum += (b - a) * (b - a);
        ++count;
    }
    (void)dt_s;
    return std::sqrt(0.5 * sum / count);
}

}  // namespace gyrocal::sim::testing
