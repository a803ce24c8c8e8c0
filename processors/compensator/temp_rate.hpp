#pragma once
// Rate of temperature change from the sample stream, for models with "dTdt" or "heating" terms.
//
// dT/dt is the least-squares slope of temp_c against time over the last `window_s` seconds
// (running sums, O(1) per sample). A slope, not a finite difference: the temperature line's
// noise (~0.01 degC per sample) differenced at 100 Hz would be ~1 degC/s of noise, while over a
// 10 s window the slope's noise is ~sigma*sqrt(12/(N*T^2)) ~ 1e-4 degC/s. The branch ("heating")
// is +1 while the slope exceeds +deadband, -1 below -deadband, and keeps its last value between
// (a plateau belongs to the branch that reached it).
#include <cstdint>
#include <deque>

#include "model/terms.hpp"

namespace gyrocal::compensate {

class TempRateEstimator {
public:
    explicit TempRateEstimator(double window_s = 10.0,
                               double heating_deadband_c_per_s = 1.0 / 600.0);
    void Add(int64_t utime, double temp_c);
    // [degC/s]; NaN until the window holds samples spanning at least half its length.
    double rate_c_per_s() const { return rate_; }
    // +1 heating, -1 cooling, NaN before the first clear slope.
    double heating() const { return heating_; }
    void Reset();

private:
    struct Point {
        double t_s;
        double temp_c;
    };
    double window_s_;
    double deadband_;
    std::deque<Point> points_;
    int64_t origin_utime_ = 0;
    bool has_origin_ = false;
    double st_ = 0, stt_ = 0, sy_ = 0, sty_ = 0;
    double rate_ = model::kUnknown;
    double heating_ = model::kUnknown;
};

}  // namespace gyrocal::compensate
