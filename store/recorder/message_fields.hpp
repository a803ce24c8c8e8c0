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
#include <nlohmann/json.hpp>

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

// In a CopyFields(to, from): to.a = from.a; to.b = from.b; ... for the fields listed, each named
// once (by nlohmann's field-list macros, those of NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE).
#define GYROCAL_COPY_FIELD(field) to.field = from.field;
#define GYROCAL_COPY_FIELDS(...) \
    NLOHMANN_JSON_EXPAND(NLOHMANN_JSON_PASTE(GYROCAL_COPY_FIELD, __VA_ARGS__))

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
    GYROCAL_COPY_FIELDS(utime, sensor_id, seq, gyro_v, temp_v, temp_c, supply_v, has_adc,
                        gyro_counts, temp_counts, supply_counts);
}

template <class To, class From>
requires RowAndMessage<To, From, db::EncoderRow, encoder_sample_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, encoder_id, seq, counts, counts_per_rev, angle_deg);
}

template <class To, class From>
requires RowAndMessage<To, From, db::ChamberStateRow, chamber_state_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, seq, cmd_id, setpoint_c, air_c, at_setpoint, fault);
}

template <class To, class From>
requires RowAndMessage<To, From, db::PowerStateRow, power_state_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, sensor_id, seq, power_on_utime, source);
}

// The command's own run_id is stored as msg_run_id (the row's run_id is the run in force).
template <class To, class From>
requires RowAndMessage<To, From, db::ChamberCmdRow, chamber_cmd_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, cmd_id, setpoint_c, ramp_rate_c_per_min);
}

template <class To, class From>
requires RowAndMessage<To, From, db::TurntableCmdRow, turntable_cmd_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, cmd_id, move_deg, rate_dps, accel_dps2);
}

template <class To, class From>
requires RowAndMessage<To, From, db::PlateauStateRow, plateau_state_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, sensor_id, state, temp_c, temp_slope_c_per_min, temp_std_c,
                        stable_for_s, averaging_progress, last_plateau_id);
}

template <class To, class From>
requires RowAndMessage<To, From, db::PlateauRow, plateau_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, sensor_id, run_id, plateau_id, setpoint_c, start_utime, end_utime,
                        first_seq, last_seq, n_samples, n_excluded_motion, seq_gaps, temp_mean_c,
                        temp_std_c, temp_sem_c, temp_slope_c_per_min, gyro_mean_v, gyro_std_v,
                        gyro_sem_v, temp_mean_v, supply_mean_v);
}

template <class To, class From>
requires RowAndMessage<To, From, db::SensitivityRow, sensitivity_point_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, sensor_id, run_id, rotation_id, start_utime, end_utime, first_seq,
                        last_seq, n_samples, temp_c, encoder_angle_deg, offset_v, offset_stderr_v,
                        integral_v_s, sensitivity_v_per_dps, sensitivity_stderr_v_per_dps, accepted,
                        reject_reason);
    // int8_t on the wire, int32_t in the row.
    to.direction = static_cast<decltype(to.direction)>(from.direction);
}

template <class To, class From>
requires RowAndMessage<To, From, db::ClosedLoopRow, analysis_t>
void CopyFields(To& to, const From& from) {
    CopyVerdictKey(to, from);
    GYROCAL_COPY_FIELDS(outcome, headline, offset_rms_v_before, offset_rms_v_after,
                        rate_rms_dps_before, rate_rms_dps_after, drift_dph_before, drift_dph_after,
                        floor_rate_rms_dps, floor_drift_dph, candidates_json, added_json,
                        result_json);
}

// The models are the conversion's own (a row's ModelRow, a message's model_t with length fields).
template <class To, class From>
requires RowAndMessage<To, From, db::CoeffSetRow, coeff_set_t>
void CopyFields(To& to, const From& from) { model::CopySetIdentity(to, from); }

template <class To, class From>
requires RowAndMessage<To, From, db::RateRow, rate_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, sensor_id, seq, rate_dps, angle_deg, temp_c, coeff_set_id,
                        range_flag);
}

// The extra values are stored as one JSON object (extra_json).
template <class To, class From>
requires RowAndMessage<To, From, db::StatusRow, status_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, process, host, pid, state, received, published, decode_errors,
                        seq_gaps, queue_drops, rejected, last_reject);
}

template <class To, class From>
requires RowAndMessage<To, From, db::RunEventRow, run_event_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, run_id, event, reason, setpoint_index, setpoint_c, sensor_ids,
                        software_version, config_json, command_line, host);
}

template <class To, class From>
requires RowAndMessage<To, From, db::NoiseRow, noise_t>
void CopyFields(To& to, const From& from) {
    GYROCAL_COPY_FIELDS(utime, sensor_id, run_id, still_s, n_segments, longest_segment_s, tau0_s,
                        arw_v_rthz, arw_stderr_v_rthz, bias_instability_v,
                        bias_instability_stderr_v, rrw_v_rts, rrw_stderr_v_rts, fit_note, tau_s,
                        adev_v, adev_lo_v, adev_hi_v, edf);
}

// The exclusions and repeatability lists are the conversion's own (other element types).
template <class To, class From>
requires RowAndMessage<To, From, db::FitReportRow, fit_report_t>
void CopyFields(To& to, const From& from) {
    CopyVerdictKey(to, from);
    GYROCAL_COPY_FIELDS(status, reason, offset_detail, sensitivity_detail, slow_noise_v,
                        slow_noise_dps, slow_noise_source);
}

}  // namespace gyrocal::recorder
