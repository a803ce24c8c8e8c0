#include "temp_rate.hpp"

#include <cmath>

namespace gyrocal::compensate {

TempRateEstimator::TempRateEstimator(double window_s, double deadband)
    : window_s_(window_s), deadband_(deadband) {}

void TempRateEstimator::Reset() {
    points_.clear();
    has_origin_ = false;
    st_ = stt_ = sy_ = sty_ = 0;
    rate_ = heating_ = model::kUnknown;
}

void TempRateEstimator::Add(int64_t utime, double temp_c) {
    if (!std::isfinite(temp_c)) return;
    if (!has_origin_) {
        origin_utime_ = utime;
        has_origin_ = true;
    }
    // Times relative to an origin near the window keep the running sums well conditioned; once an
    // hour the origin moves to the window's start and the sums are recomputed (O(window) then).
    double t = 1e-6 * static_cast<double>(utime - origin_utime_);
    if (t > 3600.0 && !points_.empty()) {
        const int64_t shift_us = std::llround(points_.front().t_s * 1e6);
        const double shift = 1e-6 * static_cast<double>(shift_us);
        origin_utime_ += shift_us;
        st_ = stt_ = sy_ = sty_ = 0;
        for (Point& p : points_) {
            p.t_s -= shift;
            st_ += p.t_s;
            stt_ += p.t_s * p.t_s;
            sy_ += p.temp_c;
            sty_ += p.t_s * p.temp_c;
        }
        t = 1e-6 * static_cast<double>(utime - origin_utime_);
    }
    points_.push_back({t, temp_c});
    st_ += t;
    stt_ += t * t;
    sy_ += temp_c;
    sty_ += t * temp_c;
    while (!points_.empty() && points_.front().t_s < t - window_s_) {
        const Point& p = points_.front();
        st_ -= p.t_s;
        stt_ -= p.t_s * p.t_s;
        sy_ -= p.temp_c;
        sty_ -= p.t_s * p.temp_c;
        points_.pop_front();
    }
    const double n = static_cast<double>(points_.size());
    const double span = points_.back().t_s - points_.front().t_s;
    if (points_.size() < 3 || span < 0.5 * window_s_) {
        rate_ = model::kUnknown;
        return;
    }
    const double var_t = stt_ - st_ * st_ / n;
    rate_ = var_t > 0 ? (sty_ - st_ * sy_ / n) / var_t : model::kUnknown;
    if (rate_ > deadband_) heating_ = 1.0;
    if (rate_ < -deadband_) heating_ = -1.0;
}

}  // namespace gyrocal::compensate
