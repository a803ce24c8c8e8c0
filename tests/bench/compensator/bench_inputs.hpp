#pragma once
// The compensator benchmarks' inputs: two coefficient sets and a realistic sample stream.
//
// Sets (ADXRS610-like numbers: 2.5 V offset, 6 mV/(deg/s), valid -40..85 degC):
//   quadratic  the seed's model: offset and sensitivity {1, dT, dT^2};
//   extended   every term kind the compensator tracks an input for: offset {1, dT, dT^2, dT^3,
//              dTdt(20), heating(2), supply, warmup(400)}, sensitivity {1, dT, dT^2, direction}.
// Both carry a full covariance, so the compensator also propagates the rate's standard error,
// as it does live.
//
// Stream: a unit on a moving table in a ramping chamber, generated through the extended set
// (its trackers and terms), so every input moves: temperature a 5 degC/min triangle between 15
// and 35 degC (480 s period: dT/dt and the heating/cooling branch switch) plus 0.02 degC white
// noise; rate 30 deg/s sine with an 8 s period (the direction switches); gyro white noise 2 mV
// (about 0.3 deg/s, the order of the ADXRS610's 0.05 deg/s/sqrt(Hz) over its bandwidth); supply
// 5 V with a 5 mV, 60 s swing and 0.5 mV noise. The values are the same for either model: only
// the compensator's work differs.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "processors/model/convert.hpp"

namespace gyrocal::bench {

enum class ModelKind { kQuadratic, kExtended };
std::optional<ModelKind> ParseModelKind(const std::string& text);  // "quadratic" | "extended"
const char* ToString(ModelKind kind);

model::CoeffSet BenchSet(ModelKind kind, const std::string& sensor_id);

struct RawSample {
    double gyro_v = 0.0;    // [V]
    double temp_c = 0.0;    // [degC]
    double supply_v = 0.0;  // [V]
};

// Triangle period of the temperature [s]: a stream of a whole number of periods can be replayed
// in a loop without a temperature jump.
inline constexpr double kTempPeriodS = 480.0;

// n samples at rate_hz [Hz] of unit number `unit` (which shifts its phases and noise seed),
// sample k taken at k / rate_hz seconds after power-on.
std::vector<RawSample> SyntheticStream(int unit, double rate_hz, int64_t n);

}  // namespace gyrocal::bench
