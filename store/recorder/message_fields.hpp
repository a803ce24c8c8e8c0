#pragma once
// The fields a stored row (store/db/rows.hpp) shares by name with the LCM message it is recorded
// from, one list per stored message type, used in both directions: message -> row when recording
// (record_mapper.cpp), row -> message when replaying (replay_source.cpp), recovering
// (recovery.cpp) and exporting samples (store/format/samples_csv.cpp). A field added to a message
// and its row is added here once.
//
// What is not shared by name stays with each conversion: the run in force and recv_utime (rows
// only), a message's length fields (num_*), and fields stored in another form (a command's own
// run_id as msg_run_id, STATUS' extra values as JSON, a fit report's lists, a set's models).
// store/db stays free of LCM: this header is the recorder's.
#include <concepts>

#include "gyrocal/analysis_t.hpp"
#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/noise_t.hpp"
#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "gyrocal/rate_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/status_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"
#include "processors/model/convert.hpp"
#include "store/db/rows.hpp"

namespace gyrocal::recorder {

// True when {To, From} is {Row, Msg} in either order: the list serves both directions.
template <class To, class From, class Row, class Msg>
concept RowAndMessage = (std::same_as<To, Row> && std::same_as<From, Msg>) ||
                        (std::same_as<To, Msg> && std::same_as<From, Row>);

// What a verdict on a coefficient set (an analysis, a fit report) names it by: the set's key
// (run, sensor, coeff_set_id, source), when it was given and whether it is the final one.
template <class To, class From>
void CopyVerdictKey(To& to, const From& from) {
    model::CopySetKey(to, from);
    to.is_final = from.is_final;
}

template <class To, class From>
requires RowAndMessage<To, From, db::GyroRow, gyro_sample_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.sensor_id = from.sensor_id;
    to.seq = from.seq;
    to.gyro_v = from.gyro_v;
    to.temp_v = from.temp_v;
    to.temp_c = from.temp_c;
    to.supply_v = from.supply_v;
    to.has_adc = from.has_adc;
    to.gyro_counts = from.gyro_counts;
    to.temp_counts = from.temp_counts;
    to.supply_counts = from.supply_counts;
}

template <class To, class From>
requires RowAndMessage<To, From, db::EncoderRow, encoder_sample_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.encoder_id = from.encoder_id;
    to.seq = from.seq;
    to.counts = from.counts;
    to.counts_per_rev = from.counts_per_rev;
    to.angle_deg = from.angle_deg;
}

template <class To, class From>
requires RowAndMessage<To, From, db::ChamberStateRow, chamber_state_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.seq = from.seq;
    to.cmd_id = from.cmd_id;
    to.setpoint_c = from.setpoint_c;
    to.air_c = from.air_c;
    to.at_setpoint = from.at_setpoint;
    to.fault = from.fault;
}

template <class To, class From>
requires RowAndMessage<To, From, db::PowerStateRow, power_state_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.sensor_id = from.sensor_id;
    to.seq = from.seq;
    to.power_on_utime = from.power_on_utime;
    to.source = from.source;
}

// The command's own run_id is stored as msg_run_id (the row's run_id is the run in force).
template <class To, class From>
requires RowAndMessage<To, From, db::ChamberCmdRow, chamber_cmd_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.cmd_id = from.cmd_id;
    to.setpoint_c = from.setpoint_c;
    to.ramp_rate_c_per_min = from.ramp_rate_c_per_min;
}

template <class To, class From>
requires RowAndMessage<To, From, db::TurntableCmdRow, turntable_cmd_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.cmd_id = from.cmd_id;
    to.move_deg = from.move_deg;
    to.rate_dps = from.rate_dps;
    to.accel_dps2 = from.accel_dps2;
}

template <class To, class From>
requires RowAndMessage<To, From, db::PlateauStateRow, plateau_state_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.sensor_id = from.sensor_id;
    to.state = from.state;
    to.temp_c = from.temp_c;
    to.temp_slope_c_per_min = from.temp_slope_c_per_min;
    to.temp_std_c = from.temp_std_c;
    to.stable_for_s = from.stable_for_s;
    to.averaging_progress = from.averaging_progress;
    to.last_plateau_id = from.last_plateau_id;
}

template <class To, class From>
requires RowAndMessage<To, From, db::PlateauRow, plateau_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.sensor_id = from.sensor_id;
    to.run_id = from.run_id;
    to.plateau_id = from.plateau_id;
    to.setpoint_c = from.setpoint_c;
    to.start_utime = from.start_utime;
    to.end_utime = from.end_utime;
    to.first_seq = from.first_seq;
    to.last_seq = from.last_seq;
    to.n_samples = from.n_samples;
    to.n_excluded_motion = from.n_excluded_motion;
    to.seq_gaps = from.seq_gaps;
    to.temp_mean_c = from.temp_mean_c;
    to.temp_std_c = from.temp_std_c;
    to.temp_sem_c = from.temp_sem_c;
    to.temp_slope_c_per_min = from.temp_slope_c_per_min;
    to.gyro_mean_v = from.gyro_mean_v;
    to.gyro_std_v = from.gyro_std_v;
    to.gyro_sem_v = from.gyro_sem_v;
    to.temp_mean_v = from.temp_mean_v;
    to.supply_mean_v = from.supply_mean_v;
}

template <class To, class From>
requires RowAndMessage<To, From, db::SensitivityRow, sensitivity_point_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.sensor_id = from.sensor_id;
    to.run_id = from.run_id;
    to.rotation_id = from.rotation_id;
    to.start_utime = from.start_utime;
    to.end_utime = from.end_utime;
    to.first_seq = from.first_seq;
    to.last_seq = from.last_seq;
    to.n_samples = from.n_samples;
    // int8_t on the wire, int32_t in the row.
    to.direction = static_cast<decltype(to.direction)>(from.direction);
    to.temp_c = from.temp_c;
    to.encoder_angle_deg = from.encoder_angle_deg;
    to.offset_v = from.offset_v;
    to.offset_stderr_v = from.offset_stderr_v;
    to.integral_v_s = from.integral_v_s;
    to.sensitivity_v_per_dps = from.sensitivity_v_per_dps;
    to.sensitivity_stderr_v_per_dps = from.sensitivity_stderr_v_per_dps;
    to.accepted = from.accepted;
    to.reject_reason = from.reject_reason;
}

template <class To, class From>
requires RowAndMessage<To, From, db::ClosedLoopRow, analysis_t>
void CopyFields(To& to, const From& from) {
    CopyVerdictKey(to, from);
    to.outcome = from.outcome;
    to.headline = from.headline;
    to.offset_rms_v_before = from.offset_rms_v_before;
    to.offset_rms_v_after = from.offset_rms_v_after;
    to.rate_rms_dps_before = from.rate_rms_dps_before;
    to.rate_rms_dps_after = from.rate_rms_dps_after;
    to.drift_dph_before = from.drift_dph_before;
    to.drift_dph_after = from.drift_dph_after;
    to.floor_rate_rms_dps = from.floor_rate_rms_dps;
    to.floor_drift_dph = from.floor_drift_dph;
    to.candidates_json = from.candidates_json;
    to.added_json = from.added_json;
    to.result_json = from.result_json;
}

// The models are the conversion's own (a row's ModelRow, a message's model_t with length fields).
template <class To, class From>
requires RowAndMessage<To, From, db::CoeffSetRow, coeff_set_t>
void CopyFields(To& to, const From& from) { model::CopySetIdentity(to, from); }

template <class To, class From>
requires RowAndMessage<To, From, db::RateRow, rate_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.sensor_id = from.sensor_id;
    to.seq = from.seq;
    to.rate_dps = from.rate_dps;
    to.angle_deg = from.angle_deg;
    to.temp_c = from.temp_c;
    to.coeff_set_id = from.coeff_set_id;
    to.range_flag = from.range_flag;
}

// The extra values are stored as one JSON object (extra_json).
template <class To, class From>
requires RowAndMessage<To, From, db::StatusRow, status_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.process = from.process;
    to.host = from.host;
    to.pid = from.pid;
    to.state = from.state;
    to.received = from.received;
    to.published = from.published;
    to.decode_errors = from.decode_errors;
    to.seq_gaps = from.seq_gaps;
    to.queue_drops = from.queue_drops;
    to.rejected = from.rejected;
    to.last_reject = from.last_reject;
}

template <class To, class From>
requires RowAndMessage<To, From, db::RunEventRow, run_event_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.run_id = from.run_id;
    to.event = from.event;
    to.reason = from.reason;
    to.setpoint_index = from.setpoint_index;
    to.setpoint_c = from.setpoint_c;
    to.sensor_ids = from.sensor_ids;
    to.software_version = from.software_version;
    to.config_json = from.config_json;
    to.command_line = from.command_line;
    to.host = from.host;
}

template <class To, class From>
requires RowAndMessage<To, From, db::NoiseRow, noise_t>
void CopyFields(To& to, const From& from) {
    to.utime = from.utime;
    to.sensor_id = from.sensor_id;
    to.run_id = from.run_id;
    to.still_s = from.still_s;
    to.n_segments = from.n_segments;
    to.longest_segment_s = from.longest_segment_s;
    to.tau0_s = from.tau0_s;
    to.arw_v_rthz = from.arw_v_rthz;
    to.arw_stderr_v_rthz = from.arw_stderr_v_rthz;
    to.bias_instability_v = from.bias_instability_v;
    to.bias_instability_stderr_v = from.bias_instability_stderr_v;
    to.rrw_v_rts = from.rrw_v_rts;
    to.rrw_stderr_v_rts = from.rrw_stderr_v_rts;
    to.fit_note = from.fit_note;
    to.tau_s = from.tau_s;
    to.adev_v = from.adev_v;
    to.adev_lo_v = from.adev_lo_v;
    to.adev_hi_v = from.adev_hi_v;
    to.edf = from.edf;
}

// The exclusions and repeatability lists are the conversion's own (other element types).
template <class To, class From>
requires RowAndMessage<To, From, db::FitReportRow, fit_report_t>
void CopyFields(To& to, const From& from) {
    CopyVerdictKey(to, from);
    to.status = from.status;
    to.reason = from.reason;
    to.offset_detail = from.offset_detail;
    to.sensitivity_detail = from.sensitivity_detail;
    to.slow_noise_v = from.slow_noise_v;
    to.slow_noise_dps = from.slow_noise_dps;
    to.slow_noise_source = from.slow_noise_source;
}

}  // namespace gyrocal::recorder
