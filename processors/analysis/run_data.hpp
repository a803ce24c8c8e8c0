#pragma once
// What the analysis reads about one sensor of one run: plain data, filled by a database loader,
// a CSV reader or a test, through BuildSensorRun so that all of them share one definition of
// "still" and "moving".
//
// Still vs moving: the table moves wherever the encoder angle changes between two consecutive
// encoder readings. Such intervals (merged when closer than merge_gap_s) are widened by guard_s
// on both sides (the module's low-pass filter, table ringing, encoder/gyro clock skew) and every
// gyro sample inside is excluded from the still data.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace gyrocal::analysis {

inline constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

struct GyroSample {
    int64_t utime = 0;       // [us]
    int64_t seq = 0;         // producer sequence number
    double temp_c = kNan;    // [degC] measured temperature
    double gyro_v = kNan;    // [V] rate output
    double supply_v = kNan;  // [V] measured supply; NaN when not recorded
};

struct EncoderSample {
    int64_t utime = 0;        // [us]
    double angle_deg = kNan;  // [deg]
};

struct MotionInterval {
    int64_t start_utime = 0;  // [us] first encoder reading of the move (guard not included)
    int64_t end_utime = 0;    // [us] last
    double angle_change_deg = 0.0;
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
    int64_t first_sample_utime = 0;      // [us] power-on proxy: the first sample of the run
    std::vector<GyroSample> still;       // time-ordered, finite temp_c and gyro_v, table at rest
    std::vector<MotionInterval> motion;  // table moves seen on the encoder
    std::vector<PlateauInput> plateaus;
    std::vector<SensitivityInput> sensitivities;
    int64_t n_raw_samples = 0;     // before exclusions
    int64_t n_moving_samples = 0;  // excluded: inside a (guarded) motion interval
    int64_t n_bad_samples = 0;     // excluded: non-finite temp_c / gyro_v, out of order
    int64_t n_seq_gaps = 0;        // missing sequence numbers
    bool has_encoder = false;
};

struct BuildOptions {
    double guard_s = 1.0;       // [s] excluded before and after every move
    double merge_gap_s = 0.5;   // [s] moves closer than this are one
    double min_move_deg = 0.0;  // [deg] a change above this between readings is motion
    static BuildOptions Defaults() { return {}; }
};

// Motion intervals from encoder readings (any order; sorted here).
std::vector<MotionInterval> MotionFromEncoder(std::vector<EncoderSample> encoder,
                                              const BuildOptions& options);

// Builds the analysis input from raw samples (any order; sorted by utime here) and encoder
// readings. No encoder readings: every sample counts as still (has_encoder false, reported).
SensorRun BuildSensorRun(const std::string& sensor_id, std::vector<GyroSample> raw,
                         const std::vector<EncoderSample>& encoder,
                         std::vector<PlateauInput> plateaus,
                         std::vector<SensitivityInput> sensitivities,
                         const BuildOptions& options = BuildOptions::Defaults());

}  // namespace gyrocal::analysis
