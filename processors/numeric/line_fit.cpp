#include "processors/numeric/line_fit.hpp"

#include <algorithm>
#include <cmath>

namespace gyrocal::numeric {
namespace {

// The line through n points from their sums about the means (sxx = sum (t - mean_t)^2, ...):
// mean_y is the fitted value at mean_t, last_from_mean_s the newest time minus mean_t.
LineFit FromCentredSums(int n, double sxx, double sxy, double syy, double mean_y,
                        double last_from_mean_s) {
    LineFit f;
    f.n = n;
    if (n < 3 || !(sxx > 0)) return f;
    f.ok = true;
    f.slope_per_s = sxy / sxx;
    f.value_at_last = mean_y + f.slope_per_s * last_from_mean_s;
    const double rss = std::max(0.0, syy - f.slope_per_s * sxy);
    f.resid_std = std::sqrt(rss / (n - 2));
    f.slope_stderr_per_s = f.resid_std / std::sqrt(sxx);
    return f;
}

}  // namespace

LineFit FitLine(const std::vector<double>& t, const std::vector<double>& y) {
    const int n = static_cast<int>(std::min(t.size(), y.size()));
    if (n < 3) return FromCentredSums(n, 0, 0, 0, 0, 0);
    double mt = 0, my = 0;
    for (int i = 0; i < n; ++i) {
        mt += t[i];
        my += y[i];
    }
    mt /= n;
    my /= n;
    double sxx = 0, sxy = 0, syy = 0;
    for (int i = 0; i < n; ++i) {
        const double dt = t[i] - mt, dy = y[i] - my;
        sxx += dt * dt;
        sxy += dt * dy;
        syy += dy * dy;
    }
    return FromCentredSums(n, sxx, sxy, syy, my, t[n - 1] - mt);
}

SlidingLine::SlidingLine(double window_s)
    : window_us_(static_cast<int64_t>(std::llround(window_s * 1e6))) {}

void SlidingLine::Clear() {
    points_.clear();
    st_ = sy_ = stt_ = sty_ = syy_ = 0;
}

double SlidingLine::span_s() const {
    if (points_.size() < 2) return 0;
    return (points_.back().first - points_.front().first) * 1e-6;
}

void SlidingLine::Reanchor() {
    t0_us_ = points_.front().first;
    y0_ = points_.front().second;
    st_ = sy_ = stt_ = sty_ = syy_ = 0;
    for (const auto& [t, y] : points_) Accumulate(t, y, +1.0);
}

void SlidingLine::Accumulate(int64_t utime, double y, double sign) {
    const double dt = (utime - t0_us_) * 1e-6, dy = y - y0_;
    st_ += sign * dt;
    sy_ += sign * dy;
    stt_ += sign * dt * dt;
    sty_ += sign * dt * dy;
    syy_ += sign * dy * dy;
}

void SlidingLine::Add(int64_t utime, double y) {
    if (points_.empty()) {
        t0_us_ = utime;
        y0_ = y;
    }
    points_.emplace_back(utime, y);
    Accumulate(utime, y, +1.0);
    bool popped = false;
    while (points_.size() > 1 && utime - points_.front().first > window_us_) {
        Accumulate(points_.front().first, points_.front().second, -1.0);
        points_.pop_front();
        popped = true;
    }
    if (popped && points_.front().first - t0_us_ > 2 * window_us_) Reanchor();
}

LineFit SlidingLine::Fit() const {
    const int count = static_cast<int>(points_.size());
    if (count < 3) return FromCentredSums(count, 0, 0, 0, 0, 0);
    const double n = count;
    const double mt = st_ / n, my = sy_ / n;
    const double t_last = (points_.back().first - t0_us_) * 1e-6;
    return FromCentredSums(count, stt_ - n * mt * mt, sty_ - n * mt * my, syy_ - n * my * my,
                           y0_ + my, t_last - mt);
}

PrefixLine::PrefixLine(size_t n) : t_(n + 1, 0), y_(n + 1, 0), tt_(n + 1, 0), ty_(n + 1, 0) {}

void PrefixLine::Set(size_t i, double t, double y) {
    t_[i + 1] = t_[i] + t;
    y_[i + 1] = y_[i] + y;
    tt_[i + 1] = tt_[i] + t * t;
    ty_[i + 1] = ty_[i] + t * y;
}

double PrefixLine::Slope(size_t a, size_t b) const {
    const double n = static_cast<double>(b - a);
    const double st = t_[b] - t_[a], sy = y_[b] - y_[a];
    const double den = n * (tt_[b] - tt_[a]) - st * st;
    return den > 0 ? (n * (ty_[b] - ty_[a]) - st * sy) / den : 0.0;
}

double PrefixLine::Mean(size_t a, size_t b) const {
    return (y_[b] - y_[a]) / static_cast<double>(b - a);
}

}  // namespace gyrocal::numeric
