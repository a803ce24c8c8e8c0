#pragma once
// Straight lines y = a + b t fitted by least squares in closed form: over a whole series
// (FitLine, on centred data), over a window sliding with the newest sample (SlidingLine, O(1) per
// sample) and over any index range of a stored series (PrefixLine, O(1) per range from prefix
// sums). The plateau detector judges temperature stability with them, batch means detrend with
// them (series_stats.hpp), the noise tracker finds thermally quiet stretches with them.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

namespace gyrocal::numeric {

struct LineFit {
    bool ok = false;  // false with fewer than 3 points or zero time span
    int n = 0;
    double slope_per_s = 0;         // [unit of y / s]
    double value_at_last = 0;       // [unit of y] fitted value at the newest time
    double resid_std = 0;           // [unit of y] scatter about the line (n - 2 dof)
    double slope_stderr_per_s = 0;  // [unit of y / s] white-noise standard error of the slope
};

// t in seconds (any origin), same length as y.
LineFit FitLine(const std::vector<double>& t_s, const std::vector<double>& y);

// Straight line over the samples of the last window_s seconds, updated in O(1) per sample with
// running sums about a local anchor (re-anchored, i.e. recomputed, once the anchor is more than
// two windows old so the sums never lose precision).
class SlidingLine {
public:
    explicit SlidingLine(double window_s);
    void Add(int64_t utime, double y);  // utime increasing
    void Clear();
    size_t size() const { return points_.size(); }
    double span_s() const;  // [s] newest - oldest time in the window
    LineFit Fit() const;

private:
    void Reanchor();
    // Adds (sign +1) or removes (sign -1) one point's terms of the sums about (t0_us_, y0_).
    void Accumulate(int64_t utime, double y, double sign);
    int64_t window_us_;
    std::deque<std::pair<int64_t, double>> points_;
    int64_t t0_us_ = 0;
    double y0_ = 0;
    double st_ = 0, sy_ = 0, stt_ = 0, sty_ = 0, syy_ = 0;
};

// Prefix sums of a series (t_i, y_i), filled in index order: the mean of y and the least-squares
// slope of y against t over any index range [a, b) in O(1), e.g. windows centred on each point.
// The sums are not centred: keep t small (relative to the series' start).
class PrefixLine {
public:
    explicit PrefixLine(size_t n);
    void Set(size_t i, double t, double y);  // i = 0, 1, ... in turn
    double Slope(size_t a, size_t b) const;  // [unit of y / unit of t]; 0 when t does not spread
    double Mean(size_t a, size_t b) const;   // b > a

private:
    std::vector<double> t_, y_, tt_, ty_;
};

}  // namespace gyrocal::numeric
