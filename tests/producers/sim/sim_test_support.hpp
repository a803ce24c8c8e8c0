#pragma once
// Helpers shared by the simulator tests: a sink that keeps everything, and the Allan deviation.
#include <cmath>
#include <cstdint>
#include <vector>

#include "producers/sim/rig.hpp"

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
    for (double* noise :
         {&c.noise.noise_density_dps_rthz, &c.noise.bias_instability_dps,
          &c.noise.rate_random_walk_dps_rts, &c.noise.temp_noise_v, &c.thermal.air_noise_c,
          &c.supply.ripple_v, &c.supply.drift_std_v, &c.supply.noise_v}) {
        *noise = 0.0;
    }
    c.adc.bits = 0;  // no quantization
    return c;
}

// A heat-up, a +90 and a -90 deg turn at the hot setpoint, and a cool-down, in seconds from
// `start_utime`: the chamber is set to `hot_c` at once, the turns start at `hot_s` and are given
// `turn_s` each, then the chamber is set to `cool_c` and the rig runs on to `end_s`.
struct HeatTurnCool {
    double hot_c;
    int64_t hot_s;
    int64_t turn_s;
    double cool_c;
    int64_t end_s;
};

inline void Run(Rig& rig, RigSink& sink, int64_t start_utime, const HeatTurnCool& p) {
    constexpr int64_t kUsPerS = 1'000'000;
    const int64_t turns_utime = start_utime + p.hot_s * kUsPerS;
    rig.ChamberCommand(1, p.hot_c, 0.0);
    rig.RunUntil(turns_utime, sink);
    rig.TurntableCommand(1, 90.0, 0.0, 0.0);
    rig.RunUntil(turns_utime + p.turn_s * kUsPerS, sink);
    rig.TurntableCommand(2, -90.0, 0.0, 0.0);
    rig.RunUntil(turns_utime + 2 * p.turn_s * kUsPerS, sink);
    rig.ChamberCommand(2, p.cool_c, 0.0);
    rig.RunUntil(start_utime + p.end_s * kUsPerS, sink);
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
