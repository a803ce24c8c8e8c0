#pragma once
// Statistics of a window of samples whose noise is correlated in time.
//
// The module's low-pass filter (and any chamber or supply wander) makes neighbouring samples
// correlated, so std/sqrt(n) understates the standard error of a mean by sqrt(1 + 2 sum rho_k)
// (about 4.4x for an AR(1) with rho = 0.9). We use BATCH MEANS: cut the window into B contiguous
// batches of equal count; when a batch is much longer than the correlation time the batch means
// are nearly independent, and SEM = sd(batch means) / sqrt(B). The batch means are first
// detrended by a straight line (B - 2 degrees of freedom) so that a slow drift inside the
// window (a plateau is allowed a small slope) is not reported as noise: the mean of a window
// with a linear drift is still the value at its centre, without random error from the drift.
// The estimate itself scatters by about 1/sqrt(2 (B - 2)) relative (17% for B = 20).
// With fewer than 2*4 samples (B < 4 batches of 2) it falls back to std/sqrt(n).
//
// For SHORT windows (a rotation's 2 s rest windows: 200 samples, too few for good batches) the
// effective-sample-size route is used instead: the integrated autocorrelation time
// tau_int = 1 + 2 sum_k rho_k (in samples) by Geyer's initial positive sequence, pooled over
// several series, so SEM = sqrt(var * tau_int / n) and the noise's two-sided spectral level is
// var * tau_int * dt.
//
// Also a straight-line fit y = a + b t (closed form on centred data) used for the slope and
// scatter criteria, and a sliding-window version with O(1) updates.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

namespace gyrocal::stats {

struct MeanStats {
    int n = 0;
    double mean = 0;  // [unit of x]
    double std = 0;   // [unit of x] sample standard deviation (n - 1)
    double sem = 0;   // [unit of x] standard error of the mean by detrended batch means
    int batches = 0;  // batches used for sem; 0 = fell back to std/sqrt(n)
};

// x in time order. batches >= 4 requested; fewer are used when n is small. Empty x -> n = 0 and
// NaN mean/std/sem.
MeanStats DescribeSeries(const std::vector<double>& x, int batches);

struct NoiseLevel {
    double var = 0;      // [unit^2] variance about each series' mean
    double tau_int = 1;  // [samples] integrated autocorrelation time, >= 1
    int n = 0;           // [count] samples pooled
};

// Pools the residuals of each series about its own mean (short windows: a drift inside them is
// negligible against the noise); series with fewer than 4 samples are ignored. var = NaN when
// nothing is left.
NoiseLevel PooledNoiseLevel(const std::vector<std::vector<double>>& series);

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
    int64_t window_us_;
    std::deque<std::pair<int64_t, double>> points_;
    int64_t t0_us_ = 0;
    double y0_ = 0;
    double st_ = 0, sy_ = 0, stt_ = 0, sty_ = 0, syy_ = 0;
};

}  // namespace gyrocal::stats
