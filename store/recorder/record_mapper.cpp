#include "record_mapper.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "bus/decode.hpp"
#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/noise_t.hpp"
#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/rate_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/status_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"
#include "model/convert.hpp"

namespace gyrocal::record {
namespace {

using namespace gyrocal::store;

GyroRow ToRow(const gyro_sample_t& m) {
    GyroRow r;
    r.sensor_id = m.sensor_id;
    r.utime = m.utime;
    r.seq = m.seq;
    r.gyro_v = m.gyro_v;
    r.temp_v = m.temp_v;
    r.temp_c = m.temp_c;
    r.supply_v = m.supply_v;
    r.has_adc = m.has_adc;
    r.gyro_counts = m.gyro_counts;
    r.temp_counts = m.temp_counts;
    r.supply_counts = m.supply_counts;
    return r;
}

EncoderRow ToRow(const encoder_sample_t& m) {
    EncoderRow r;
    r.encoder_id = m.encoder_id;
    r.utime = m.utime;
    r.seq = m.seq;
    r.counts = m.counts;
    r.counts_per_rev = m.counts_per_rev;
    r.angle_deg = m.angle_deg;
    return r;
}

ChamberStateRow ToRow(const chamber_state_t& m) {
    ChamberStateRow r;
    r.utime = m.utime;
    r.seq = m.seq;
    r.cmd_id = m.cmd_id;
    r.setpoint_c = m.setpoint_c;
    r.air_c = m.air_c;
    r.at_setpoint = m.at_setpoint;
    r.fault = m.fault;
    return r;
}

PowerStateRow ToRow(const power_state_t& m) {
    PowerStateRow r;
    r.sensor_id = m.sensor_id;
    r.utime = m.utime;
    r.seq = m.seq;
    r.power_on_utime = m.power_on_utime;
    r.source = m.source;
    return r;
}

ChamberCmdRow ToRow(const chamber_cmd_t& m) {
    ChamberCmdRow r;
    r.msg_run_id = m.run_id;
    r.utime = m.utime;
    r.cmd_id = m.cmd_id;
    r.setpoint_c = m.setpoint_c;
    r.ramp_rate_c_per_min = m.ramp_rate_c_per_min;
    return r;
}

TurntableCmdRow ToRow(const turntable_cmd_t& m) {
    TurntableCmdRow r;
    r.msg_run_id = m.run_id;
    r.utime = m.utime;
    r.cmd_id = m.cmd_id;
    r.move_deg = m.move_deg;
    r.rate_dps = m.rate_dps;
    r.accel_dps2 = m.accel_dps2;
    return r;
}

PlateauStateRow ToRow(const plateau_state_t& m) {
    PlateauStateRow r;
    r.sensor_id = m.sensor_id;
    r.utime = m.utime;
    r.state = m.state;
    r.temp_c = m.temp_c;
    r.temp_slope_c_per_min = m.temp_slope_c_per_min;
    r.temp_std_c = m.temp_std_c;
    r.stable_for_s = m.stable_for_s;
    r.averaging_progress = m.averaging_progress;
    r.last_plateau_id = m.last_plateau_id;
    return r;
}

PlateauRow ToRow(const plateau_t& m) {
    PlateauRow r;
    r.run_id = m.run_id;
    r.sensor_id = m.sensor_id;
    r.plateau_id = m.plateau_id;
    r.utime = m.utime;
    r.setpoint_c = m.setpoint_c;
    r.start_utime = m.start_utime;
    r.end_utime = m.end_utime;
    r.first_seq = m.first_seq;
    r.last_seq = m.last_seq;
    r.n_samples = m.n_samples;
    r.n_excluded_motion = m.n_excluded_motion;
    r.seq_gaps = m.seq_gaps;
    r.temp_mean_c = m.temp_mean_c;
    r.temp_std_c = m.temp_std_c;
    r.temp_sem_c = m.temp_sem_c;
    r.temp_slope_c_per_min = m.temp_slope_c_per_min;
    r.gyro_mean_v = m.gyro_mean_v;
    r.gyro_std_v = m.gyro_std_v;
    r.gyro_sem_v = m.gyro_sem_v;
    r.temp_mean_v = m.temp_mean_v;
    r.supply_mean_v = m.supply_mean_v;
    return r;
}

SensitivityRow ToRow(const sensitivity_point_t& m) {
    SensitivityRow r;
    r.run_id = m.run_id;
    r.sensor_id = m.sensor_id;
    r.rotation_id = m.rotation_id;
    r.utime = m.utime;
    r.start_utime = m.start_utime;
    r.end_utime = m.end_utime;
    r.first_seq = m.first_seq;
    r.last_seq = m.last_seq;
    r.n_samples = m.n_samples;
    r.direction = m.direction;
    r.temp_c = m.temp_c;
    r.encoder_angle_deg = m.encoder_angle_deg;
    r.offset_v = m.offset_v;
    r.offset_stderr_v = m.offset_stderr_v;
    r.integral_v_s = m.integral_v_s;
    r.sensitivity_v_per_dps = m.sensitivity_v_per_dps;
    r.sensitivity_stderr_v_per_dps = m.sensitivity_stderr_v_per_dps;
    r.accepted = m.accepted;
    r.reject_reason = m.reject_reason;
    return r;
}

ModelRow ToModel(const model_t& m) {
    ModelRow r;
    model::CopyModelScalars(r, m);
    r.coeffs = m.coeffs;
    r.covariance = m.covariance;
    return r;
}

CoeffSetRow ToRow(const coeff_set_t& m) {
    CoeffSetRow r;
    model::CopySetIdentity(r, m);
    r.offset = ToModel(m.offset);
    r.sensitivity = ToModel(m.sensitivity);
    return r;
}

RateRow ToRow(const rate_t& m) {
    RateRow r;
    r.sensor_id = m.sensor_id;
    r.utime = m.utime;
    r.seq = m.seq;
    r.rate_dps = m.rate_dps;
    r.angle_deg = m.angle_deg;
    r.temp_c = m.temp_c;
    r.coeff_set_id = m.coeff_set_id;
    r.range_flag = m.range_flag;
    return r;
}

StatusRow ToRow(const status_t& m) {
    StatusRow r;
    r.utime = m.utime;
    r.process = m.process;
    r.host = m.host;
    r.pid = m.pid;
    r.state = m.state;
    r.received = m.received;
    r.published = m.published;
    r.decode_errors = m.decode_errors;
    r.seq_gaps = m.seq_gaps;
    r.queue_drops = m.queue_drops;
    r.rejected = m.rejected;
    r.last_reject = m.last_reject;
    nlohmann::json extra = nlohmann::json::object();
    for (size_t i = 0; i < m.extra_names.size() && i < m.extra_values.size(); ++i) {
        // JSON has no NaN/inf: those become null.
        extra[m.extra_names[i]] = std::isfinite(m.extra_values[i])
                                      ? nlohmann::json(m.extra_values[i])
                                      : nlohmann::json(nullptr);
    }
    r.extra_json = extra.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    return r;
}

RunEventRow ToRow(const run_event_t& m) {
    RunEventRow r;
    r.run_id = m.run_id;
    r.utime = m.utime;
    r.event = m.event;
    r.reason = m.reason;
    r.setpoint_index = m.setpoint_index;
    r.setpoint_c = m.setpoint_c;
    r.sensor_ids = m.sensor_ids;
    r.software_version = m.software_version;
    r.config_json = m.config_json;
    r.command_line = m.command_line;
    r.host = m.host;
    return r;
}

NoiseRow ToRow(const noise_t& m) {
    NoiseRow r;
    r.run_id = m.run_id;
    r.sensor_id = m.sensor_id;
    r.utime = m.utime;
    r.still_s = m.still_s;
    r.n_segments = m.n_segments;
    r.longest_segment_s = m.longest_segment_s;
    r.tau0_s = m.tau0_s;
    r.arw_v_rthz = m.arw_v_rthz;
    r.arw_stderr_v_rthz = m.arw_stderr_v_rthz;
    r.bias_instability_v = m.bias_instability_v;
    r.bias_instability_stderr_v = m.bias_instability_stderr_v;
    r.rrw_v_rts = m.rrw_v_rts;
    r.rrw_stderr_v_rts = m.rrw_stderr_v_rts;
    r.fit_note = m.fit_note;
    r.tau_s = m.tau_s;
    r.adev_v = m.adev_v;
    r.adev_lo_v = m.adev_lo_v;
    r.adev_hi_v = m.adev_hi_v;
    r.edf = m.edf;
    return r;
}

FitReportRow ToRow(const fit_report_t& m) {
    FitReportRow r;
    r.run_id = m.run_id;
    r.sensor_id = m.sensor_id;
    r.source = m.source;
    r.coeff_set_id = m.coeff_set_id;
    r.utime = m.utime;
    r.is_final = m.is_final;
    r.status = m.status;
    r.reason = m.reason;
    r.offset_detail = m.offset_detail;
    r.sensitivity_detail = m.sensitivity_detail;
    r.slow_noise_v = m.slow_noise_v;
    r.slow_noise_dps = m.slow_noise_dps;
    r.slow_noise_source = m.slow_noise_source;
    for (const fit_exclusion_t& e : m.excluded)
        r.excluded.push_back({e.kind, e.item_id, e.temp_c, e.value, e.residual, e.residual_sigma,
                              e.statistic, e.threshold, e.reason});
    for (const repeatability_t& e : m.repeats)
        r.repeats.push_back({e.temp_c, e.first_plateau_id, e.second_plateau_id, e.first_temp_c,
                             e.second_temp_c, e.first_approach, e.second_approach, e.offset_diff_v,
                             e.offset_diff_stderr_v, e.offset_diff_dps, e.offset_diff_stderr_dps,
                             e.z, e.verdict});
    return r;
}

// Rows whose run is the one in force (the message carries none, or only the sender's view).
template <class R>
void StampRun(R& r, const std::string& run_id) {
    if constexpr (std::is_same_v<R, PlateauRow> || std::is_same_v<R, SensitivityRow> ||
                  std::is_same_v<R, CoeffSetRow> || std::is_same_v<R, RunEventRow> ||
                  std::is_same_v<R, NoiseRow> || std::is_same_v<R, FitReportRow>) {
        (void)r;
        (void)run_id;
    } else {
        r.run_id = run_id;
    }
}

}  // namespace

std::optional<uint64_t> Fingerprint(const void* data, int size) {
    if (data == nullptr || size < 8) return std::nullopt;
    const auto* b = static_cast<const uint8_t*>(data);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v = (v << 8) | b[i];
    return v;
}

std::string FingerprintHex(const void* data, int size) {
    const auto fp = Fingerprint(data, size);
    if (!fp) return "";
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(*fp));
    return buf;
}

RecordMapper::RecordMapper(MapperOptions options, std::string initial_run_id)
    : options_(options), run_id_(std::move(initial_run_id)) {}

Mapped RecordMapper::Map(const std::string& channel, const void* data, int size,
                         int64_t recv_utime) {
    Mapped out;
    const std::optional<uint64_t> fp = Fingerprint(data, size);

    auto raw = [&](const char* reason) {
        RawEventRow r;
        r.run_id = run_id_;
        r.channel = channel;
        r.recv_utime = recv_utime;
        r.fingerprint_hex = FingerprintHex(data, size);
        r.reason = reason;
        if (data != nullptr && size > 0) {
            const auto* b = static_cast<const uint8_t*>(data);
            r.data.assign(b, b + size);
        }
        out.run_id = run_id_;
        out.row = std::move(r);
    };

    // Decodes as Msg when the fingerprint is Msg's; true when this type claimed the message.
    auto try_type = [&]<class Msg>(Msg msg) -> bool {
        if (!fp || *fp != static_cast<uint64_t>(Msg::getHash())) return false;
        if (!DecodeMessage(msg, data, size)) {
            raw("decode_error");
            out.loss.decode_errors = 1;
            return true;
        }
        if constexpr (std::is_same_v<Msg, run_event_t>) {
            // The event belongs to its own run; then the run in force changes.
            out.run_id = msg.run_id;
            out.essential = true;
            if (msg.event == "stop" || msg.event == "abort") {
                run_id_.clear();
            } else {
                run_id_ = msg.run_id;
            }
        } else {
            out.run_id = run_id_;
        }
        if constexpr (requires { msg.seq; }) {
            const SeqReport rep = seq_.Observe(channel, msg.seq);
            out.loss.seq_gaps = rep.missing;
            out.loss.seq_backwards = rep.backwards ? 1 : 0;
        }
        if constexpr (std::is_same_v<Msg, rate_t>) {
            if (!options_.store_rates) return true;
        }
        auto row = ToRow(msg);
        StampRun(row, run_id_);
        row.recv_utime = recv_utime;
        if constexpr (std::is_same_v<Msg, coeff_set_t> || std::is_same_v<Msg, fit_report_t> ||
                      std::is_same_v<Msg, noise_t>)
            out.essential = true;
        out.row = std::move(row);
        return true;
    };

    const bool known =
        try_type(gyro_sample_t{}) || try_type(encoder_sample_t{}) ||
        try_type(chamber_state_t{}) || try_type(plateau_t{}) || try_type(sensitivity_point_t{}) ||
        try_type(coeff_set_t{}) || try_type(rate_t{}) || try_type(status_t{}) ||
        try_type(run_event_t{}) || try_type(chamber_cmd_t{}) || try_type(turntable_cmd_t{}) ||
        try_type(plateau_state_t{}) || try_type(power_state_t{}) || try_type(noise_t{}) ||
        try_type(fit_report_t{});
    if (!known) raw("unknown_type");
    return out;
}

}  // namespace gyrocal::record
