#pragma once
// Time bins of the still data: the unit the regressions work on.
//
// Why bins (default 10 s): (1) white rate noise averages down as 1/sqrt(samples), so a 10 s mean
// at 100 Hz carries 1/30 of the per-sample noise and the effects (mV, over minutes) stand out;
// (2) a run of hours is ~1e6 samples but ~1e3 bins, so every regression, cross-validation fold and
// 1-D search is cheap; (3) what is left in the bin means is correlated noise (bias instability,
// rate random walk, a slow supply or chamber wobble): bins do not remove it, so the tests that
// use them account for residual autocorrelation explicitly (regress.hpp).
// Bins sit on a grid from the first sample; a bin is kept only when it is filled to min_fill of
// its expected samples (no move, no gap inside). Consecutive kept bins form a segment.
//
// Per-bin regressors, each computed from MEASURED data only (never from a truth):
//   dtemp_dt_c_per_s: central difference of the neighbouring bins' mean temperatures (a 2-bin
//     window: unbiased on a ramp, noise ~ sem(T)/bin_s), one-sided at a segment edge, the
//     within-bin slope for a lone bin;
//   heating: a play operator of width branch_width_c on the bin temperatures: +1 once the
//     temperature has risen by half the width from its last extreme, -1 once fallen, 0 before
//     either (the branch is unknown at power-on);
//   time_since_power_s: bin centre minus the run's first sample.
#include <cstdint>
#include <vector>

#include "model/terms.hpp"
#include "run_data.hpp"

namespace gyrocal::analysis {

struct Bin {
    int64_t start_utime = 0;             // [us] grid cell
    int64_t end_utime = 0;               // [us]
    double mid_utime = 0.0;              // [us] mean sample time
    int n = 0;                           // samples
    double temp_c = kNan;                // [degC] mean
    double gyro_v = kNan;                // [V] mean
    double supply_v = kNan;              // [V] mean; NaN when any sample lacks it
    double within_slope_c_per_s = kNan;  // [degC/s] least-squares slope inside the bin
    double dtemp_dt_c_per_s = kNan;      // [degC/s]
    double heating = 0.0;                // [1] +1 heating, -1 cooling, 0 unknown
    int segment = 0;                     // index of the run of consecutive bins
    int plateau = -1;                    // index into SensorRun::plateaus when inside its window
    model::ModelInputs Inputs(int64_t first_sample_utime) const;
};

struct BinOptions {
    double bin_s = 10.0;          // [s]
    double min_fill = 0.8;        // [1] kept when n >= min_fill * expected
    double branch_width_c = 1.0;  // [degC] play-operator width for the heating/cooling branch
    static BinOptions Defaults() { return {}; }
};

// The run's nominal sample period [s] (median of still-sample spacings), 0 when < 2 samples.
double SamplePeriodS(const SensorRun& run);

std::vector<Bin> MakeBins(const SensorRun& run, const BinOptions& options);

// Heating/cooling branch by a play operator (what a live compensator runs on temp_c too).
class BranchTracker {
public:
    explicit BranchTracker(double width_c) : half_width_c_(0.5 * width_c) {}
    // Returns +1 (heating), -1 (cooling) or 0 (not yet known) after this temperature.
    double Update(double temp_c);

private:
    double half_width_c_;
    double memory_c_ = kNan;
    double branch_ = 0.0;
};

// Noise floor the data allows, from the scatter of bin means inside plateau windows (pooled over
// plateaus with >= 3 bins, each plateau's own mean removed): the offset RMS a perfect model would
// leave at this bin size. Falls back to the plateaus' standard errors scaled to the bin length
// (white-noise assumption) when no plateau holds 3 bins. NaN when neither is possible.
struct Floor {
    double offset_rms_v = kNan;  // [V]
    int dof = 0;
    bool from_standard_errors = false;
};
// values: per-bin values to take the scatter of (default: the bins' gyro_v); the analysis passes
// the residuals of its extended model, so that an effect that varies inside a plateau window (a
// supply drift) does not count as noise.
Floor NoiseFloor(const SensorRun& run, const std::vector<Bin>& bins, double bin_s,
                 const std::vector<double>* values = nullptr);

}  // namespace gyrocal::analysis
