#pragma once
// Statistics of a series of samples whose noise is correlated in time.
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
#include <vector>

namespace gyrocal::numeric {

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

}  // namespace gyrocal::numeric
