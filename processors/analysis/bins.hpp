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
// its expected samples with samples at rest (no move, no gap inside). Consecutive kept bins form
// a segment. The bins dropped below the fill limit are counted (BinDrops), and so are those
// dropped outside the plateau windows of a run whose motion is unknown (run_data.hpp).
//
// Model inputs of a bin: the means over its samples of the inputs the trackers of
// model/inputs.hpp give at each sample - the very trackers the compensators run - fed with EVERY
// sample of the run from the power-on (at rest or not), so that a coefficient fitted here means
// what the compensators apply. Inputs that depend on a tracker parameter (dT/dt time constant,
// branch width) are tracked once per parameter asked for. A term's value in a bin is the term at
// the bin's mean inputs (terms that are not linear in their input, dT^2 or warm-up, differ from the
// mean of the per-sample values by far less than the noise: (bin_s / tau)^2 / 24 relative).
#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "processors/analysis/run_data.hpp"
#include "processors/model/inputs.hpp"

namespace gyrocal::analysis {

struct Bin {
    int64_t start_utime = 0;           // [us] grid cell
    int64_t end_utime = 0;             // [us]
    double mid_utime = 0.0;            // [us] mean sample time
    int n = 0;                         // samples
    double temp_c = kNan;              // [degC] mean
    double gyro_v = kNan;              // [V] mean
    double supply_v = kNan;            // [V] mean; NaN when any sample lacks it
    double time_since_power_s = kNan;  // [s] mean
    int segment = 0;                   // index of the run of consecutive bins
    int plateau = -1;                  // index into SensorRun::plateaus when inside its window
    // Other channels (NaN when not recorded): the chamber air at the bin's mean time (linear
    // between the readings around it, or the nearest one within a bin length); the table at rest:
    // its angle modulo a revolution, the direction (+1 / -1, 0 before any turn) and mean rate of
    // the last turn before the bin (NaN before any turn).
    double air_c = kNan;               // [degC]
    double table_deg = kNan;           // [deg] in [0, 360)
    double last_turn_dir = kNan;       // [1]
    double last_turn_rate_dps = kNan;  // [deg/s] |turn angle| / turn duration
};

// Bins of still samples left out, and the still samples they held (a bin with a move inside is
// not counted here: its samples are the run's n_moving_samples).
struct BinDrops {
    int bins = 0;
    int64_t samples = 0;
};

struct BinOptions {
    double bin_s = 10.0;    // [s]
    double min_fill = 0.8;  // [1] kept when n >= min_fill * expected
    static BinOptions Defaults() { return {}; }
};

// The run's nominal sample period [s] (median of sample spacings), 0 when < 2 samples; for a run
// without its samples (binned elsewhere: bins_incremental.hpp), its sample_period_s.
double SamplePeriodS(const SensorRun& run);

// Chamber air at t [us] from the readings around it (either may be null): linear between them,
// else the nearest within tolerance_us, else NaN. The one rule of Bin::air_c, for the bins of a
// whole run (bins.cpp) and for the bins built as the samples come (bins_incremental.cpp).
double AirBetween(const AirSample* before, const AirSample* after, double t, double tolerance_us);

// The bin means of the tracked inputs for one tracker configuration, one value per bin.
struct TrackedInputs {
    std::vector<double> rate, branch, heating;
};

// Where a run binned elsewhere gets its tracked inputs (bins_incremental.hpp), since its samples
// are not there to track them again.
class TrackedInputSource {
public:
    virtual ~TrackedInputSource() = default;
    virtual TrackedInputs Track(const gyrocal_tracker_config_t& config) const = 0;
};

class BinnedRun {
public:
    // Keeps a reference to `run`: it must outlive this object.
    BinnedRun(const SensorRun& run, const BinOptions& options);
    // Bins made elsewhere (bins_incremental.hpp) from the samples `run` describes (its samples
    // may be empty): `bins` complete (segments, power, air, table, plateau), their tracked inputs
    // from `inputs`. Keeps a reference to `run`.
    // `underfilled` and `unknown_motion`: the bins it left out (as underfilled() says).
    BinnedRun(const SensorRun& run, double bin_s, std::vector<Bin> bins,
              std::shared_ptr<const TrackedInputSource> inputs, BinDrops underfilled = {},
              BinDrops unknown_motion = {});

    const std::vector<Bin>& bins() const { return bins_; }
    size_t size() const { return bins_.size(); }
    const SensorRun& run() const { return run_; }
    double bin_s() const { return bin_s_; }
    // Bins at rest left out below min_fill of their expected samples (gaps, the run's ends).
    const BinDrops& underfilled() const { return underfilled_; }
    // Bins left out because they lie outside every plateau window of a run whose motion is
    // unknown (SensorRun::motion_unknown).
    const BinDrops& unknown_motion() const { return unknown_motion_; }

    // The inputs of bin i as trackers with `config` give them (means over its samples).
    model::ModelInputs Inputs(size_t i, const gyrocal_tracker_config_t& config) const;
    // The value of one registry term in every bin (tracked with the parameter the term names).
    // Throws model::ModelError on an unknown term.
    Eigen::VectorXd Column(const std::string& term, double t0_c) const;
    Eigen::MatrixXd Design(const std::vector<std::string>& terms, double t0_c) const;
    // A model's value in every bin (its own tracker configuration), extrapolated outside range.
    Eigen::VectorXd Values(const model::Model& model) const;

private:
    const TrackedInputs& Track(const gyrocal_tracker_config_t& config) const;

    const SensorRun& run_;
    double bin_s_;
    std::vector<Bin> bins_;
    BinDrops underfilled_, unknown_motion_;
    std::vector<int> bin_of_sample_;                                      // -1 = not in a kept bin
    std::shared_ptr<const TrackedInputSource> inputs_;                    // set: binned elsewhere
    mutable std::map<std::pair<double, double>, TrackedInputs> tracked_;  // by (tau, width)
};

// The table's state at rest in every bin (Bin::table_deg, last_turn_*) from run.moves, and the
// plateau each bin lies in (Bin::plateau): shared by both ways of binning.
void AddTableState(const SensorRun& run, std::vector<Bin>& bins);
void AddPlateaus(const SensorRun& run, std::vector<Bin>& bins);
// Whether the bin [start_utime, end_utime) lies inside a plateau window of `run`.
bool InPlateauWindow(const SensorRun& run, int64_t start_utime, int64_t end_utime);

// A grid cell's sums of still samples closed into a bin, the one way of both binnings (BinnedRun
// from the samples, BinSnapshot from the incremental cells), cells given in grid order: a cell
// below min_fill of the samples expected, or outside the plateau windows where the run's motion
// is unknown, is dropped and counted; a kept cell that does not follow the last kept one starts a
// segment. The bin's other inputs (time since power-on, air, table) are each binning's own.
class CellCloser {
public:
    CellCloser(const SensorRun& run, const BinOptions& o, double period_s)
        : run_(run),
          bin_us_(static_cast<int64_t>(std::llround(o.bin_s * 1e6))),
          min_fill_(o.min_fill),
          expected_(o.bin_s / period_s) {}

    // Sums: cell, n, n_supply and the sums sum_utime [us], sum_temp [degC], sum_gyro [V],
    // sum_supply [V] of its samples.
    template <class Sums>
    std::optional<Bin> Close(const Sums& c) {
        if (c.n < min_fill_ * expected_) {
            ++underfilled.bins, underfilled.samples += c.n;
            return std::nullopt;
        }
        Bin b;
        b.start_utime = run_.first_sample_utime + c.cell * bin_us_;
        b.end_utime = b.start_utime + bin_us_;
        if (run_.motion_unknown && !InPlateauWindow(run_, b.start_utime, b.end_utime)) {
            ++unknown_motion.bins, unknown_motion.samples += c.n;
            return std::nullopt;
        }
        b.n = c.n;
        b.mid_utime = c.sum_utime / c.n;
        b.temp_c = c.sum_temp / c.n;
        b.gyro_v = c.sum_gyro / c.n;
        b.supply_v = c.n_supply == c.n ? c.sum_supply / c.n : kNan;
        if (c.cell != last_cell_ + 1) ++segment_;
        b.segment = segment_;
        last_cell_ = c.cell;
        return b;
    }

    BinDrops underfilled, unknown_motion;

private:
    const SensorRun& run_;
    int64_t bin_us_;
    double min_fill_, expected_;
    int64_t last_cell_ = -2;
    int segment_ = -1;
};

// Noise floor of a per-bin series (residuals of a model): the Allan deviation at the bin length,
// sqrt(sum (v[i+1] - v[i])^2 / (2 m)) over the m pairs of consecutive bins in one segment. A model
// error that changes slowly from bin to bin cancels in the differences, so this is what white
// noise leaves in one bin, whatever the model, on plateaus and ramps alike. NaN with no pair.
struct Floor {
    double offset_rms_v = kNan;  // [V]
    int pairs = 0;
};
Floor NoiseFloor(const std::vector<Bin>& bins, const Eigen::VectorXd& values);

}  // namespace gyrocal::analysis
