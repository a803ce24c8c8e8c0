#pragma once
// Allan deviation of a gyro from still stretches, IEEE Std 952 style, and the noise terms fitted
// to it. Pure numerics, unit-agnostic: values are in the unit of the series (the pipeline feeds
// gyro_v, so volts; divide by the sensitivity for deg/s).
//
// Overlapping Allan variance of a segment of M regular bins y_k of length tau0, at tau = m tau0,
// from the phase x_k = tau0 sum_{j<k} y_j:
//     AVAR(tau) = sum_{k=0}^{M-2m} (x_{k+2m} - 2 x_{k+m} + x_k)^2 / (2 tau^2 (M - 2m + 1)).
// Segments (separate still stretches) are combined by adding their sums and term counts; a
// segment contributes only to tau <= M tau0 / 4 (enough overlapping terms to mean something).
// Equivalent degrees of freedom per segment: the smaller of the white-FM and flicker-FM formulas
// of Howe, Allan and Barnes (1981) (conservative where the noise type is mixed), summed over
// segments; the 68 % interval of AVAR is edf AVAR / chi2_edf at 0.84 and 0.16.
//
// Noise terms (IEEE 952 Annex C, without quantisation and rate ramp):
//     AVAR(tau) = N^2 / tau + B^2 + K^2 tau / 3
// N angle random walk [unit/sqrt(Hz)], B the flat (bias instability) level of the Allan deviation
// [unit] (IEEE 952's bias instability coefficient is B / 0.664), K rate random walk
// [unit/sqrt(s)]. Linear in (N^2, B^2, K^2): weighted least squares over the tau points with
// var(AVAR_j) = 2 model_j^2 / edf_j (iterated from the measured values), negative terms dropped
// and the rest refitted. K is fitted only when the points reach tau >= min_rrw_tau_s (300 s):
// below that a random walk cannot be told from the flicker floor's slow rise (an OU bank's
// components with correlation times of ~100-1000 s), and a K fitted there, extrapolated to a run
// of hours, would make the slow noise several times too large. Points at different tau share data,
// so the WLS covariance understates the uncertainty; the standard errors are the jackknife over
// segments (leave one segment out, refit) when there are at least 3 segments, else the WLS ones
// (said in the note).
//
// The slow noise of a window mean: a plateau's standard error comes from the scatter inside its
// window and misses noise slower than the window. Its variance, for a mean over w_s within a run
// of span_s (the fit takes out the run's mean, so frequencies below 1 / span_s do not count):
//     flicker (Allan level B, PSD h/f with B^2 = 2 ln2 h):  h * I(pi w / span),
//         I(a) = integral_a^inf sin^2(u) / u^3 du   (the window's sinc^2 transfer, u = pi f w)
//     random walk K: K^2 span / 6   (variance of a random walk about its mean over the span)
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace gyrocal::noise {

// Running sums of one segment at each tau of the grid.
struct SegmentSums {
    double length_s = 0;         // [s] M tau0
    int64_t bins = 0;            // M
    std::vector<double> sum_sq;  // per tau index: sum of squared second differences of x
    std::vector<int64_t> terms;  // per tau index: M - 2m + 1 (0 when the segment is too short)
};

struct AllanPoint {
    double tau_s = 0;
    double adev = 0;     // [unit]
    double adev_lo = 0;  // [unit] 68 % interval
    double adev_hi = 0;
    double edf = 0;     // [1]
    int64_t terms = 0;  // overlapping differences summed
};

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct NoiseTerms {
    double arw = kNaN, arw_se = kNaN;    // N [unit/sqrt(Hz)]
    double bias = kNaN, bias_se = kNaN;  // B [unit]
    double rrw = kNaN, rrw_se = kNaN;    // K [unit/sqrt(s)]
    bool ok = false;
    std::string note;  // which terms were dropped, how the errors were found
};

// The tau grid: m = 1, 2, 3, 4, 6, 8, 11, 16, ... (about two per octave) up to max_m.
std::vector<int64_t> TauGrid(int64_t max_m);

// The sums of one segment of bins y (length tau0_s each) at each m of `grid` with
// m <= M / bins_per_m (4: the header's rule for one segment standing alone; pooled over many
// short stretches, 2 still leaves every m terms enough: M - 2m + 1 >= 1 per segment).
SegmentSums SumSegment(const std::vector<double>& y, double tau0_s,
                       const std::vector<int64_t>& grid, int64_t bins_per_m = 4);

// Segments that disagree with the others: a disturbance inside a still stretch (a knock, a step
// of the offset) inflates that segment's Allan variance by orders of magnitude and would make the
// whole unit look noisy. Under one noise process a segment's AVAR over the others' is
// F(edf_s, edf_rest) at each tau; a segment is left out when, at some tau >= 1 s, that ratio
// exceeds both the F quantile at alpha / (segments x taus) (Bonferroni) and 4 (an Allan deviation
// twice the others': far beyond the change of a gyro's noise with temperature). The worst is left
// out first and the test repeated, at most a third of the segments. Returns the segments kept;
// `note` says what was left out.
std::vector<SegmentSums> ScreenSegments(const std::vector<SegmentSums>& segments, double tau0_s,
                                        const std::vector<int64_t>& grid, double alpha,
                                        std::string& note);

// Allan deviation over segments (skipping `skip` when >= 0: for the jackknife).
std::vector<AllanPoint> Combine(const std::vector<SegmentSums>& segments, double tau0_s,
                                const std::vector<int64_t>& grid, int skip = -1);

// Fits N, B, K to the points with tau >= min_tau_s; jackknife errors over `segments`.
NoiseTerms FitTerms(const std::vector<SegmentSums>& segments, double tau0_s,
                    const std::vector<int64_t>& grid, double min_tau_s,
                    double min_rrw_tau_s = 300.0);

// [unit^2] variance of a window_s mean of the slow noise (flicker B, random walk K) within a run
// of span_s (see header). Non-finite B or K count as 0.
double SlowNoiseVariance(double bias, double rrw, double window_s, double span_s);
// I(a) of the header, a > 0.
double WindowFlickerIntegral(double a);

}  // namespace gyrocal::noise
