#pragma once
// One gyro sample as every processor reads it: the plateau detector, the rotation estimator, the
// noise tracker, the compensator and the analysis (and the fitter's ramp mode through it). A node
// that needs more per-sample facts keeps them beside this struct (the plateau detector's temp_v
// and still/moving flag), never in a copy of it.
#include <cstdint>
#include <limits>

namespace gyrocal::motion {

struct GyroSample {
    int64_t utime = 0;                                           // [us] producer clock
    int64_t seq = 0;                                             // [count] per-producer sequence
    double gyro_v = std::numeric_limits<double>::quiet_NaN();    // [V] rate output
    double temp_c = std::numeric_limits<double>::quiet_NaN();    // [degC] measured temperature
    double supply_v = std::numeric_limits<double>::quiet_NaN();  // [V] NaN = not measured
};

// The one conversion to a sample: anything whose fields are named as gyro_sample_t's (the GYRO_<id>
// message, the simulator's reading, the store's gyro row).
template <class Gyro>
GyroSample GyroSampleOf(const Gyro& g) {
    return GyroSample{.utime = g.utime,
                      .seq = g.seq,
                      .gyro_v = g.gyro_v,
                      .temp_c = g.temp_c,
                      .supply_v = g.supply_v};
}

}  // namespace gyrocal::motion
