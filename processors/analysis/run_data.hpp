#pragma once
// What the analysis reads about one sensor of one run: plain data, filled by a database loader,
// a CSV reader or a test, through BuildSensorRun so that all of them share one definition of
// "still" and "moving" and of the power-on time.
//
// Still vs moving: the live detector's definition (motion::MoveDetector, processors/motion/
// table_motion.hpp, with its dither threshold and settle time) run over the encoder's counts; a
// sample within guard_s of a move (before its start or after its end: TableMove::Near) is moving.
// No encoder readings: every sample counts as still (reported). Encoder readings whose time is not
// after the previous one's, or without counts_per_rev, are dropped and counted (n_bad_encoder).
// Readings recorded but fewer than 2 usable: the encoder was there and failed, so the table's
// motion is unknown, not "at rest" (motion_unknown): the run's turns (the sequencer turns the table
// at every setpoint) would sit in the still data as rate signals hundreds of times the effects
// sought. A lab engineer expects those turns kept out, not averaged in: the bins then keep only the
// plateau windows, where the sequencer holds the table at rest by procedure (it turns only after a
// window is collected), and the notes say so. No readings at all is a run recorded without an
// encoder (a CSV without one, a lab without one): every sample counts as still, as before, and the
// notes say so (and how many rotations the run recorded, whose turns are then in the still data).
// Power-on: the power records of the unit (POWER_<id> on the bus, a CSV time_since_power_s
// column); each distinct power_on_utime is a power cycle. None: the first sample is taken as the
// power-on time and the result says it was assumed.
// Other measured channels the analysis reads when they were recorded (never invented when not):
// the chamber's air temperature (CHAMBER_STATE air_c, a CSV chamber_c column) through
// AddChamberAir, and the table's position from the encoder (its rest position before the first
// move and every move's end: the angle at rest, the last turn's direction and rate).
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "processors/motion/gyro_sample.hpp"
#include "processors/motion/table_motion.hpp"

namespace gyrocal::analysis {

inline constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// A gyro sample of the run (the one struct, motion/gyro_sample.hpp).
using GyroSample = motion::GyroSample;

struct PowerRecord {
    int64_t utime = 0;           // [us] when it was sent
    int64_t power_on_utime = 0;  // [us] when the unit was powered
    std::string source;          // "rig", "csv time_since_power_s", ...
};

// A chamber air reading (chamber_state_t).
struct AirSample {
    int64_t utime = 0;    // [us]
    double air_c = kNan;  // [degC] chamber air
};

// A plateau as the plateau detector published it (plateau_t).
struct PlateauInput {
    int64_t plateau_id = 0;
    int64_t start_utime = 0;    // [us] averaging window
    int64_t end_utime = 0;      // [us]
    double temp_mean_c = kNan;  // [degC]
    double temp_sem_c = kNan;   // [degC] standard error of the mean
    double gyro_mean_v = kNan;  // [V]
    double gyro_sem_v = kNan;   // [V]
    int64_t n_samples = 0;
};

// A sensitivity point as the rotation estimator published it (sensitivity_point_t).
struct SensitivityInput {
    int64_t rotation_id = 0;
    int64_t utime = 0;     // [us]
    double temp_c = kNan;  // [degC]
    int direction = 0;     // +1 / -1
    double sensitivity_v_per_dps = kNan;
    double stderr_v_per_dps = kNan;
    bool accepted = true;
};

struct SensorRun {
    std::string sensor_id;
    std::vector<GyroSample> samples;       // every usable sample, time-ordered
    std::vector<uint8_t> still;            // per sample: 1 when the table was at rest
    std::vector<motion::TableMove> moves;  // table moves seen on the encoder
    std::vector<int64_t> power_on_utimes;  // [us] distinct power-on times, ascending
    std::string power_on_source;           // where they came from (or the assumption)
    bool power_on_assumed = false;         // no record: the first sample is the power-on
    std::vector<PlateauInput> plateaus;
    std::vector<SensitivityInput> sensitivities;
    int64_t first_sample_utime = 0;  // [us]
    int64_t n_raw_samples = 0;       // before exclusions
    int64_t n_moving_samples = 0;    // at rest: no (inside a guarded move)
    int64_t n_bad_samples = 0;       // excluded: non-finite temp_c / gyro_v, out of order
    int64_t n_seq_gaps = 0;          // missing sequence numbers
    bool has_encoder = false;
    int64_t n_bad_encoder = 0;    // encoder readings dropped: time not after the previous, no cpr
    bool motion_unknown = false;  // readings recorded, fewer than 2 usable (see the header)
    int64_t initial_counts = 0;   // [count] first encoder reading (the rest position before moves)
    int32_t counts_per_rev = 0;   // [count/rev] of that reading; 0 without encoder
    std::vector<AirSample> air;   // chamber air, time-ordered, finite; empty: not recorded
    int64_t n_bad_air = 0;        // air readings excluded (non-finite, repeated time)
    // [s] the median sample spacing, for a run whose samples are not kept (binned as they came:
    // bins_incremental.hpp); 0 when the samples are here (SamplePeriodS computes it from them).
    double sample_period_s = 0.0;
    int64_t n_still() const { return static_cast<int64_t>(samples.size()) - n_moving_samples; }
};

struct BuildOptions {
    // [s] excluded before and after every move (gyrocal-plateau's default)
    double guard_s = motion::kDefaultGuardS;
    motion::MoveDetectorConfig move = motion::MoveDetectorConfig::Defaults();
    static BuildOptions Defaults() { return {}; }
};

// The moves of the encoder readings (any order; sorted here, equal times in the order given).
// A reading whose time is not after the previous one's, or without counts_per_rev, is dropped;
// `n_bad`, when given, is set to how many were.
std::vector<motion::TableMove> MovesFromEncoder(std::vector<motion::EncoderReading> encoder,
                                                const BuildOptions& options,
                                                int64_t* n_bad = nullptr);

// Builds the analysis input from raw samples, encoder readings and power records (any order;
// sorted here).
SensorRun BuildSensorRun(const std::string& sensor_id, std::vector<GyroSample> raw,
                         const std::vector<motion::EncoderReading>& encoder,
                         std::vector<PlateauInput> plateaus,
                         std::vector<SensitivityInput> sensitivities,
                         const std::vector<PowerRecord>& power = {},
                         const BuildOptions& options = BuildOptions::Defaults());

// Adds the chamber air readings of the run (any order; sorted here; non-finite readings and
// repeated times are dropped and counted in n_bad_air).
void AddChamberAir(SensorRun& run, std::vector<AirSample> air);

}  // namespace gyrocal::analysis
