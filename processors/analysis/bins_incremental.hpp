#pragma once
// Still bins built as the samples come, without keeping the samples: memory bounded by the number
// of bins, not of samples (the ramp fitter kept every raw sample, about 14 MB per unit-hour; a
// day of 16 units would not fit). What a bin keeps is what BinnedRun (bins.hpp) computes from the
// samples of a recorded run, so AnalyzeBinned (analyze.hpp) runs the same analysis on it.
//
// Feed: RunBinner takes a run's messages in arrival order (gyro samples per unit, the shared
// encoder, power records, chamber air, plateaus, sensitivity points); Snapshot(unit) gives the
// analysis input at any moment; a loader (the store, a CSV) feeds it the same way, in time order.
//
// What is the same as binning the raw samples (BinnedRun over BuildSensorRun):
//   cleaning      non-finite temp_c / gyro_v and samples not after the previous one are dropped
//                 and counted; sequence gaps counted; the grid's origin is the first clean sample
//   still/moving  the same MoveDetector over the encoder, the same guard before and after each
//                 move; a bin is decided once the encoder's newest reading is more than a guard
//                 past its last sample (no later move can then reach back to it), or, when the
//                 encoder is silent, once its own stream is encoder_wait_s past that (as the
//                 live plateau detector decides); a move still under way at the end of the
//                 readings lasts to the last one
//   fill          n >= min_fill x bin_s / period, the period being the median spacing of every
//                 clean sample so far (an exact histogram of spacings), judged at the snapshot
//   means         temp_c, gyro_v, supply_v, sample time: sums over the bin's samples
//   dT/dt         one tracker per time constant of TrackerGrid (the analysis' searched grid, each
//                 point's neighbours at -+5 % where an added term's standard error evaluates it,
//                 and the default), fed every clean sample from the first: identical bin means
//   branch w=1    the default tracker's branch and sign ("heating"): identical
//   time on       mean sample time minus the power-on in force (a power record, else the first
//                 sample): identical unless a power-on falls inside a bin
//   air, table,   chamber air at the bin's mean time (linear between the readings around it,
//   plateaus      else the nearest within a bin length); table state and plateau from the moves
//                 and plateaus kept (a few per turn / per setpoint)
// The approximation, and its bound: the branch of width w (heating(w), the hysteresis candidate
// searches w). The analysis asks for widths that depend on the data's temperature range, so they
// are not known while the samples pass. A play operator of every width of a log grid over the
// searched range (ratio q between neighbours) runs on every sample; a bin keeps the mean of
// (temp_c - memory) per grid width. Between two grid widths that mean is interpolated linearly in
// the half width r. Each sample's memory is a 1-Lipschitz function of r (it is clamped into
// [T - r, T + r] at every sample, and the clamp of a 1-Lipschitz function by 1-Lipschitz bounds
// stays 1-Lipschitz), so the bin mean is too, and the chord between r_a and r_b = q r_a differs
// from it by at most (r_b - r_a) / 2. In branch units (divided by r >= r_a) the error is at most
// (q - 1) / 2: 0.015 of the branch's full scale of 1 at the default q = 1.03 (so a hysteresis
// effect of 1 mV is represented within 15 uV, under a tenth of a typical 10 s bin's white noise).
// At the grid widths themselves the mean is exact (float storage: < 1e-7 of r).
// A dT/dt time constant outside TrackerGrid (none with the analysis' defaults: a test checks) is
// interpolated in log tau between its neighbours and named in Approximations(); a width outside
// the grid gives NaN (the term then cannot be fitted) and is named there too.
// Memory per bin: ~100 bytes + 8 per time constant + 4 per grid width (~0.7 kB at the defaults:
// ~0.25 MB per unit-hour at 10 s bins); plus the samples of the bins not yet decided (a few).
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/run_data.hpp"
#include "processors/motion/table_motion.hpp"

namespace gyrocal::analysis {

// The tracker parameters followed from the first sample (see the header).
struct TrackerGrid {
    std::vector<double> rate_taus_s;  // [s] exact, ascending
    std::vector<double> widths_c;     // [degC] ascending, log-spaced
    // The dT/dt time constants the analysis with `options` names (its log grid of 6 from
    // rate_tau_min_s to rate_tau_max_s, as the term names write them, and each one's neighbours
    // at 1 -+ 5 %, where an added term's parameter standard error evaluates it) and the default
    // 5 s; widths from 0.95 x branch_width_min_c to 1.05 x branch_width_max_c with neighbours at
    // most width_ratio apart. Throws std::invalid_argument when width_ratio is not in (1, 2].
    static TrackerGrid For(const AnalysisOptions& options, double width_ratio);
};

struct IncrementalOptions {
    BinOptions bins = BinOptions::Defaults();
    BuildOptions build = BuildOptions::Defaults();
    TrackerGrid grid;             // For() fills it; empty: that of the default analysis
    double width_ratio = 1.03;    // [1] the grid's, as For() was given it (error <= (q - 1) / 2)
    double encoder_wait_s = 5.0;  // [s] data time a bin waits for a silent encoder (past its guard)
    double air_wait_s = 60.0;     // [s] data time a bin waits for an air reading after its middle
    // 0: the cells stay bins.bin_s long. Else a unit's closed cells are held to at most this many:
    // when one more would exceed it, each pair of neighbours on the grid is merged into one cell
    // twice as long (sums add, means weigh by their samples: the same cell as binning at the
    // doubled length from the start, but for the chamber air, the two halves' readings weighed
    // instead of one reading at the merged mean time). Memory then stays bounded by max_cells
    // whatever the run's length; the snapshot's bin_s() says the length (bin_s x 2^k).
    int64_t max_cells = 0;
    // The bins and the grid the analysis with `analysis` reads.
    static IncrementalOptions For(const AnalysisOptions& analysis, double width_ratio = 1.03);
    static IncrementalOptions Defaults() { return For(AnalysisOptions::Defaults()); }
    std::string Validate() const;  // "" when valid, else the field and what is valid
};

// The table's moves of a run, from its encoder (shared by every unit of the run), as
// MovesFromEncoder finds them: kept as they complete (one per turn, not one per reading).
class RunMotion {
public:
    explicit RunMotion(const BuildOptions& options);
    // A reading not after the previous one, or without counts_per_rev, is ignored and counted.
    void Add(const motion::EncoderReading& e);

    bool has_encoder() const { return readings_ > 0; }
    int64_t bad_readings() const { return bad_readings_; }
    // Readings came, fewer than 2 usable: the table's motion is unknown (run_data.hpp).
    bool motion_unknown() const { return readings_ > 0 && readings_ - bad_readings_ < 2; }
    std::optional<int64_t> watermark_utime() const { return detector_.watermark_utime(); }
    std::optional<int64_t> current_start_utime() const { return detector_.current_start_utime(); }
    const std::vector<motion::TableMove>& completed() const { return moves_; }
    // The completed moves and, when one is under way, that one lasting to the newest reading.
    std::vector<motion::TableMove> Moves() const;
    int64_t initial_counts() const { return initial_counts_; }
    int32_t counts_per_rev() const { return counts_per_rev_; }

private:
    motion::MoveDetector detector_;
    std::vector<motion::TableMove> moves_;
    int64_t readings_ = 0, bad_readings_ = 0;
    int64_t last_utime_ = INT64_MIN;
    bool have_first_ = false;
    int64_t initial_counts_ = 0;
    int32_t counts_per_rev_ = 0;
};

namespace incremental {

// One decided still cell of the grid (sums over its samples) and its chamber air.
struct CellSums {
    int64_t cell = 0;  // index on the grid from the first sample
    int32_t n = 0, n_supply = 0;
    double sum_utime = 0, sum_temp = 0, sum_gyro = 0, sum_supply = 0;
    int64_t sum_rel_us =
        0;  // [us] sum of (utime - the grid's origin): exact, for time since power-on
    double sum_branch1 = 0, sum_heating1 = 0;  // the default tracker (width 1 degC)
    double air_c = kNan;                       // [degC] at the cell's mean sample time
};

// Closed cells, a fixed number per chunk; full chunks are shared, never changed.
struct Chunk {
    std::vector<CellSums> cells;
    std::vector<double> rate_sums;  // cells x taus: sums of dT/dt
    std::vector<float> lead_means;  // cells x widths: means of (temp_c - memory)
};

// Chamber air at t [us] from `air` (time-ordered), as bins.cpp's AirAt: linear between the
// readings around t, else the nearest within tolerance_us; nullopt while no reading after t has
// come and `complete` is false (one may still come).
std::optional<double> AirFrom(const std::deque<AirSample>& air, double t, double tolerance_us,
                              bool complete);

}  // namespace incremental

// One unit's run as the analysis reads it, at the moment it was taken: the run's description
// (no samples) and its closed cells, sharing the binner's full chunks.
class BinSnapshot {
public:
    bool empty() const { return !run_; }     // default-constructed: no unit
    const SensorRun& run() const;            // an empty run when empty()
    size_t cells() const;                    // closed still cells (before the fill test)
    double bin_s() const { return bin_s_; }  // [s] their length (IncrementalOptions::max_cells)
    // The bins (the fill test done with the period so far). `snapshot` must outlive the result.
    BinnedRun Binned(const BinOptions& options) const;
    // Binned() and AnalyzeBinned.
    SensorResult Analyze(const AnalysisOptions& options) const;
    // Inputs asked for that were approximated beyond the header's bound (or not available).
    std::vector<std::string> Approximations() const;

private:
    friend class UnitBinner;
    std::shared_ptr<SensorRun> run_;
    double bin_s_ = 0.0;  // [s] the cells' length
    std::shared_ptr<const TrackerGrid> grid_;
    std::vector<std::shared_ptr<const incremental::Chunk>> chunks_;
    std::shared_ptr<std::vector<std::string>> approximations_;
};

// One unit's cells as its samples come (RunBinner owns one per unit).
class UnitBinner {
public:
    UnitBinner(std::string sensor_id, const IncrementalOptions& options,
               std::shared_ptr<const TrackerGrid> grid);
    void AddGyro(const GyroSample& s, const RunMotion& motion);
    // Decides the cells the motion (or the stream's own time) now allows.
    void Settle(const RunMotion& motion, bool flush = false);
    void AddPower(const PowerRecord& p);
    void AddAir(const AirSample& a);
    void AddPlateau(const PlateauInput& p) { plateaus_.push_back(p); }
    void AddSensitivity(const SensitivityInput& p) { sensitivities_.push_back(p); }

    BinSnapshot Snapshot(const RunMotion& motion) const;
    int64_t samples() const { return n_clean_; }          // clean samples seen
    int64_t raw_samples() const { return n_raw_; }        // every sample heard
    std::optional<int64_t> first_utime() const;           // [us] first clean sample
    int64_t newest_utime() const { return last_utime_; }  // [us] newest clean sample
    size_t MemoryBytes() const;

private:
    struct Open {
        incremental::CellSums sums;
        std::vector<int64_t> utimes;  // its samples' times, for the move decision
        std::vector<double> rate_sums, lead_sums;
    };
    void Track(const GyroSample& s, Open& cell);
    // true: decided (and closed or dropped); false: must wait.
    bool Decide(Open& cell, const RunMotion& motion, bool force);
    void Close(Open& cell);
    void ResolveAir(bool force);
    void Append(const Open& cell, incremental::Chunk& to) const;
    // A closed cell into tail_ at grid index `target` (merged into the last one when the same);
    // a full tail_ becomes a shared chunk first, unless the cell merges into its last cell.
    void Put(const incremental::CellSums& s, int64_t target, const double* rate, const float* lead);
    void Coarsen();  // doubles the closed cells' length (max_cells)
    int64_t MedianSpacingUs() const;

    std::string sensor_id_;
    IncrementalOptions options_;
    std::shared_ptr<const TrackerGrid> grid_;
    int64_t bin_us_ = 0, guard_us_ = 0;
    // Cleaning and counts, as BuildSensorRun.
    int64_t n_raw_ = 0, n_clean_ = 0, n_bad_ = 0, n_gaps_ = 0, n_moving_ = 0;
    int64_t last_utime_ = INT64_MIN, last_seq_ = -1;
    bool have_seq_ = false;
    int64_t origin_ = 0;
    std::map<int64_t, int64_t> spacing_us_;  // spacing -> count (the median period)
    // Trackers: one per exact time constant (width 1), one play-operator memory per grid width.
    std::vector<gyrocal_tracker_t> rate_trackers_;
    size_t default_tau_ = 0;
    std::vector<double> memory_c_, half_c_;
    bool started_ = false;
    std::deque<Open> open_;          // oldest first; the back one is being filled
    std::deque<Open> awaiting_air_;  // decided still cells waiting for an air reading
    std::deque<AirSample> air_;      // readings still needed
    int64_t newest_air_utime_ = INT64_MIN, n_bad_air_ = 0;
    bool any_air_ = false;
    std::vector<std::shared_ptr<const incremental::Chunk>> full_;
    incremental::Chunk tail_;
    int level_ = 0;                   // closed cells are bin_us_ << level_ long
    size_t n_closed_ = 0;             // closed cells in full_ and tail_
    std::vector<PowerRecord> power_;  // distinct power-on times (few)
    std::vector<PlateauInput> plateaus_;
    std::vector<SensitivityInput> sensitivities_;
};

// A run's units and its shared encoder and chamber air, binned as the messages come.
class RunBinner {
public:
    explicit RunBinner(IncrementalOptions options);  // throws std::invalid_argument on Validate()

    void AddGyro(const std::string& sensor_id, const GyroSample& s);
    void AddEncoder(const motion::EncoderReading& e);
    void AddPower(const std::string& sensor_id, const PowerRecord& p);
    void AddAir(const AirSample& a);  // the chamber's: every unit's
    void AddPlateau(const std::string& sensor_id, const PlateauInput& p);
    void AddSensitivity(const std::string& sensor_id, const SensitivityInput& p);
    // The end of the readings: every cell still waiting is decided with what is known.
    void Flush();
    // Takes over `other`'s units (a reader that bins the units in shards, each shard fed the same
    // encoder and air: their motion is this one's). Throws std::invalid_argument when a unit is in
    // both.
    void Absorb(RunBinner&& other);

    // Throws std::out_of_range for a unit never heard.
    BinSnapshot Snapshot(const std::string& sensor_id) const;
    std::vector<std::string> sensors() const;
    const UnitBinner* unit(const std::string& sensor_id) const;
    size_t MemoryBytes() const;
    const IncrementalOptions& options() const { return options_; }

private:
    UnitBinner& Unit(const std::string& sensor_id);

    IncrementalOptions options_;
    std::shared_ptr<const TrackerGrid> grid_;
    RunMotion motion_;
    std::map<std::string, UnitBinner> units_;
    std::optional<AirSample> last_air_;  // seeds a unit heard after the air began
};

}  // namespace gyrocal::analysis
