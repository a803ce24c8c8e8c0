#pragma once
// What the store writes: one plain struct per table, with no LCM in it. The recorder maps
// decoded messages to these; tests build them directly. Doubles may be NaN (stored as NULL).
// Every row carries recv_utime [us], the recorder's wall clock at reception, which orders a
// replay; utime [us] is the producer's clock as sent.
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace gyrocal::db {

struct GyroRow {
    std::string run_id, sensor_id;
    int64_t utime = 0, seq = 0;
    double gyro_v = 0, temp_v = 0, temp_c = 0, supply_v = 0;
    bool has_adc = false;
    int32_t gyro_counts = 0, temp_counts = 0, supply_counts = 0;
    int64_t recv_utime = 0;
};

struct EncoderRow {
    std::string run_id, encoder_id;
    int64_t utime = 0, seq = 0, counts = 0;
    int32_t counts_per_rev = 0;
    double angle_deg = 0;
    int64_t recv_utime = 0;
};

struct ChamberStateRow {
    std::string run_id;
    int64_t utime = 0, seq = 0, cmd_id = 0;
    double setpoint_c = 0, air_c = 0;
    bool at_setpoint = false;
    std::string fault;
    int64_t recv_utime = 0;
};

struct PowerStateRow {
    std::string run_id, sensor_id;
    int64_t utime = 0, seq = 0, power_on_utime = 0;
    std::string source;
    int64_t recv_utime = 0;
};

struct ChamberCmdRow {
    std::string run_id, msg_run_id;
    int64_t utime = 0, cmd_id = 0;
    double setpoint_c = 0, ramp_rate_c_per_min = 0;
    int64_t recv_utime = 0;
};

struct TurntableCmdRow {
    std::string run_id, msg_run_id;
    int64_t utime = 0, cmd_id = 0;
    double move_deg = 0, rate_dps = 0, accel_dps2 = 0;
    int64_t recv_utime = 0;
};

struct PlateauStateRow {
    std::string run_id, sensor_id;
    int64_t utime = 0;
    std::string state;
    double temp_c = 0, temp_slope_c_per_min = 0, temp_std_c = 0, stable_for_s = 0,
           averaging_progress = 0;
    int64_t last_plateau_id = -1;
    int64_t recv_utime = 0;
};

struct PlateauRow {
    std::string run_id, sensor_id;
    int64_t plateau_id = 0, utime = 0;
    double setpoint_c = 0;
    int64_t start_utime = 0, end_utime = 0, first_seq = 0, last_seq = 0;
    int32_t n_samples = 0, n_excluded_motion = 0, seq_gaps = 0;
    double temp_mean_c = 0, temp_std_c = 0, temp_sem_c = 0, temp_slope_c_per_min = 0;
    double gyro_mean_v = 0, gyro_std_v = 0, gyro_sem_v = 0, temp_mean_v = 0, supply_mean_v = 0;
    int64_t recv_utime = 0;
};

struct SensitivityRow {
    std::string run_id, sensor_id;
    int64_t rotation_id = 0, utime = 0, start_utime = 0, end_utime = 0, first_seq = 0, last_seq = 0;
    int32_t n_samples = 0;
    int32_t direction = 0;
    double temp_c = 0, encoder_angle_deg = 0, offset_v = 0, offset_stderr_v = 0, integral_v_s = 0,
           sensitivity_v_per_dps = 0, sensitivity_stderr_v_per_dps = 0;
    bool accepted = false;
    std::string reject_reason;
    int64_t recv_utime = 0;
};

// A model with named terms: y = sum_i coeffs[i] * term_i(dT = temp_c - t0_c, ...).
struct ModelRow {
    std::string quantity;
    std::vector<std::string> term_names;
    std::vector<double> coeffs;
    std::vector<std::vector<double>> covariance;  // num_terms x num_terms
    double t0_c = 0, temp_min_c = 0, temp_max_c = 0, residual_rms = 0;
    int32_t n_points = 0;
    double condition_number = 0;
    std::string method;
};

struct CoeffSetRow {
    std::string run_id, sensor_id, source;
    int64_t coeff_set_id = 0, utime = 0;
    ModelRow offset, sensitivity;
    std::vector<int64_t> plateau_ids, rotation_ids;
    int64_t recv_utime = 0;
};

struct RateRow {
    std::string run_id, sensor_id;
    int64_t utime = 0, seq = 0;
    double rate_dps = 0, angle_deg = 0, temp_c = 0;
    int64_t coeff_set_id = -1;
    int32_t range_flag = 0;
    int64_t recv_utime = 0;
};

struct StatusRow {
    std::string run_id;
    int64_t utime = 0;
    std::string process, host;
    int32_t pid = 0;
    std::string state;
    int64_t received = 0, published = 0, decode_errors = 0, seq_gaps = 0, queue_drops = 0,
            rejected = 0;
    std::string last_reject;
    std::string extra_json;
    int64_t recv_utime = 0;
};

struct RunEventRow {
    std::string run_id;
    int64_t utime = 0;
    std::string event, reason;
    int32_t setpoint_index = -1;
    double setpoint_c = 0;
    std::vector<std::string> sensor_ids;
    std::string software_version, config_json, command_line, host;
    int64_t recv_utime = 0;
};

struct RawEventRow {
    std::string run_id, channel;
    int64_t recv_utime = 0;
    std::string fingerprint_hex;
    std::string reason;  // "unknown_type" or "decode_error"
    std::vector<uint8_t> data;
};

// NOISE_<id>: a unit's Allan deviation so far (schema v5: noise_estimates + noise_adev).
struct NoiseRow {
    std::string run_id, sensor_id;
    int64_t utime = 0;
    double still_s = 0, longest_segment_s = 0, tau0_s = 0;
    int32_t n_segments = 0;
    double arw_v_rthz = 0, arw_stderr_v_rthz = 0, bias_instability_v = 0,
           bias_instability_stderr_v = 0, rrw_v_rts = 0, rrw_stderr_v_rts = 0;
    std::string fit_note;
    std::vector<double> tau_s, adev_v, adev_lo_v, adev_hi_v, edf;
    int64_t recv_utime = 0;
};

// FIT_<id>: the fitter's report on a coefficient set (schema v5: fit_reports + fit_exclusions +
// repeatability).
struct FitExclusionRow {
    std::string kind;
    int64_t item_id = 0;
    double temp_c = 0, value = 0, residual = 0, residual_sigma = 0, statistic = 0, threshold = 0;
    std::string reason;
};
struct RepeatabilityRow {
    double temp_c = 0;
    int64_t first_plateau_id = 0, second_plateau_id = 0;
    double first_temp_c = 0, second_temp_c = 0;
    int32_t first_approach = 0, second_approach = 0;
    double offset_diff_v = 0, offset_diff_stderr_v = 0, offset_diff_dps = 0,
           offset_diff_stderr_dps = 0, z = 0;
    std::string verdict;
};
struct FitReportRow {
    std::string run_id, sensor_id, source;
    int64_t coeff_set_id = -1, utime = 0;
    bool is_final = false;
    std::string status, reason, offset_detail, sensitivity_detail;
    double slow_noise_v = 0, slow_noise_dps = 0;
    std::string slow_noise_source;
    std::vector<FitExclusionRow> excluded;
    std::vector<RepeatabilityRow> repeats;
    int64_t recv_utime = 0;
};

// ANALYSIS_<id>: the fitter's closed loop on every still sample (stored in `analyses`, linked to
// the coefficient set it made: (run_id, sensor_id, coeff_set_id, source)).
struct ClosedLoopRow {
    std::string run_id, sensor_id, source;
    int64_t utime = 0, coeff_set_id = -1;
    bool is_final = false;
    std::string outcome, headline, candidates_json, added_json, result_json;
    double offset_rms_v_before = 0, offset_rms_v_after = 0, rate_rms_dps_before = 0,
           rate_rms_dps_after = 0, drift_dph_before = 0, drift_dph_after = 0,
           floor_rate_rms_dps = 0, floor_drift_dph = 0;
    int64_t recv_utime = 0;
};

// Loss counts to ADD to losses(run_id, channel); never dropped by the queue.
struct LossDelta {
    int64_t seq_gaps = 0, seq_backwards = 0, decode_errors = 0, queue_drops = 0;
    bool Empty() const {
        return seq_gaps == 0 && seq_backwards == 0 && decode_errors == 0 && queue_drops == 0;
    }
    LossDelta& operator+=(const LossDelta& o) {
        seq_gaps += o.seq_gaps;
        seq_backwards += o.seq_backwards;
        decode_errors += o.decode_errors;
        queue_drops += o.queue_drops;
        return *this;
    }
};

using Row =
    std::variant<GyroRow, EncoderRow, ChamberStateRow, ChamberCmdRow, TurntableCmdRow,
                 PlateauStateRow, PlateauRow, SensitivityRow, CoeffSetRow, RateRow, StatusRow,
                 RunEventRow, RawEventRow, PowerStateRow, NoiseRow, FitReportRow, ClosedLoopRow>;

}  // namespace gyrocal::db
