#include "store/recorder/record_mapper.hpp"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "gyrocal/encoder_batch_t.hpp"
#include "gyrocal/flow_ack_t.hpp"
#include "gyrocal/flow_mark_t.hpp"
#include "gyrocal/gyro_batch_t.hpp"
#include "gyrocal/rate_batch_t.hpp"
#include "lcmtypes/bus/decode.hpp"
#include "lcmtypes/text/number.hpp"
#include "processors/model/convert.hpp"
#include "store/recorder/message_fields.hpp"

namespace gyrocal::recorder {
namespace {

using namespace gyrocal::db;

// What a row holds beyond the fields it shares with its message (message_fields.hpp): nothing
// for most types.
template <class R, class Msg>
void CopyRecordedOnly(R&, const Msg&) {}

void CopyRecordedOnly(ChamberCmdRow& r, const chamber_cmd_t& m) { r.msg_run_id = m.run_id; }

void CopyRecordedOnly(TurntableCmdRow& r, const turntable_cmd_t& m) { r.msg_run_id = m.run_id; }

ModelRow ToModel(const model_t& m) {
    ModelRow r;
    model::CopyModelScalars(r, m);
    r.coeffs = m.coeffs;
    r.covariance = m.covariance;
    return r;
}

void CopyRecordedOnly(CoeffSetRow& r, const coeff_set_t& m) {
    r.offset = ToModel(m.offset);
    r.sensitivity = ToModel(m.sensitivity);
}

void CopyRecordedOnly(StatusRow& r, const status_t& m) {
    nlohmann::json extra = nlohmann::json::object();
    for (size_t i = 0; i < m.extra_names.size() && i < m.extra_values.size(); ++i) {
        // JSON has no NaN/inf: those become null.
        extra[m.extra_names[i]] = std::isfinite(m.extra_values[i])
                                      ? nlohmann::json(m.extra_values[i])
                                      : nlohmann::json(nullptr);
    }
    r.extra_json = extra.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void CopyRecordedOnly(FitReportRow& r, const fit_report_t& m) {
    for (const fit_exclusion_t& e : m.excluded)
        r.excluded.push_back({e.kind, e.item_id, e.temp_c, e.value, e.residual, e.residual_sigma,
                              e.statistic, e.threshold, e.reason});
    for (const repeatability_t& e : m.repeats)
        r.repeats.push_back({e.temp_c, e.first_plateau_id, e.second_plateau_id, e.first_temp_c,
                             e.second_temp_c, e.first_approach, e.second_approach, e.offset_diff_v,
                             e.offset_diff_stderr_v, e.offset_diff_dps, e.offset_diff_stderr_dps,
                             e.z, e.verdict});
}

// Rows whose run is the one in force (the message carries none, or only the sender's view).
template <class R>
void StampRun(R& r, const std::string& run_id) {
    if constexpr (std::is_same_v<R, PlateauRow> || std::is_same_v<R, SensitivityRow> ||
                  std::is_same_v<R, CoeffSetRow> || std::is_same_v<R, RunEventRow> ||
                  std::is_same_v<R, NoiseRow> || std::is_same_v<R, FitReportRow> ||
                  std::is_same_v<R, ClosedLoopRow>) {
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
    return text::Printf("%016llx", static_cast<unsigned long long>(*fp));
}

RecordMapper::RecordMapper(MapperOptions options, std::string initial_run_id)
    : options_(options), run_id_(std::move(initial_run_id)) {}

// One decoded message into `out` (its row, run, loss); a rate with rates off gives no row.
template <class Msg, class R>
void RecordMapper::MapDecoded(const Msg& msg, R row, const std::string& channel, int64_t recv_utime,
                              Mapped& out) {
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
        const bus::SeqReport rep = seq_.Observe(channel, msg.seq);
        out.loss.seq_gaps += rep.missing;
        out.loss.seq_backwards += rep.backwards ? 1 : 0;
    }
    if constexpr (std::is_same_v<Msg, rate_t>) {
        if (!options_.store_rates) return;
    }
    CopyFields(row, msg);
    CopyRecordedOnly(row, msg);
    StampRun(row, run_id_);
    row.recv_utime = recv_utime;
    if constexpr (std::is_same_v<Msg, coeff_set_t> || std::is_same_v<Msg, fit_report_t> ||
                  std::is_same_v<Msg, noise_t> || std::is_same_v<Msg, analysis_t>)
        out.essential = true;
    if (!out.row) {
        out.row = std::move(row);
    } else {
        out.more.push_back(std::move(row));
    }
}

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
    auto decoded = [&]<class Msg>(Msg& msg) -> bool {
        if (!fp || *fp != static_cast<uint64_t>(Msg::getHash())) return false;
        if (bus::DecodeMessage(msg, data, size)) return true;
        raw("decode_error");
        out.loss.decode_errors = 1;
        return false;
    };
    auto claims = [&]<class Msg>(const Msg&) {
        return fp && *fp == static_cast<uint64_t>(Msg::getHash());
    };
    auto try_type = [&]<class Msg, class R>(Msg msg, R row) -> bool {
        if (!claims(msg)) return false;
        if (decoded(msg)) MapDecoded(msg, std::move(row), channel, recv_utime, out);
        return true;
    };
    // A batch: each sample as its own row, as it would have been alone.
    auto try_batch = [&]<class Batch, class R>(Batch batch, R) -> bool {
        if (!claims(batch)) return false;
        if (!decoded(batch)) return true;
        out.run_id = run_id_;
        out.control = batch.samples.empty();
        for (const auto& sample : batch.samples) MapDecoded(sample, R{}, channel, recv_utime, out);
        return true;
    };
    auto try_control = [&]<class Msg>(Msg msg) -> bool {
        if (!claims(msg)) return false;
        out.run_id = run_id_;
        out.control = true;
        return true;
    };

    // Each stored message type and the row it becomes.
    const bool known =
        try_type(gyro_sample_t{}, GyroRow{}) || try_type(encoder_sample_t{}, EncoderRow{}) ||
        try_type(chamber_state_t{}, ChamberStateRow{}) || try_type(plateau_t{}, PlateauRow{}) ||
        try_type(sensitivity_point_t{}, SensitivityRow{}) ||
        try_type(coeff_set_t{}, CoeffSetRow{}) || try_type(rate_t{}, RateRow{}) ||
        try_type(status_t{}, StatusRow{}) || try_type(run_event_t{}, RunEventRow{}) ||
        try_type(chamber_cmd_t{}, ChamberCmdRow{}) ||
        try_type(turntable_cmd_t{}, TurntableCmdRow{}) ||
        try_type(plateau_state_t{}, PlateauStateRow{}) ||
        try_type(power_state_t{}, PowerStateRow{}) || try_type(noise_t{}, NoiseRow{}) ||
        try_type(fit_report_t{}, FitReportRow{}) || try_type(analysis_t{}, ClosedLoopRow{}) ||
        try_batch(gyro_batch_t{}, GyroRow{}) || try_batch(encoder_batch_t{}, EncoderRow{}) ||
        try_batch(rate_batch_t{}, RateRow{}) || try_control(flow_mark_t{}) ||
        try_control(flow_ack_t{});
    if (!known) raw("unknown_type");
    return out;
}

}  // namespace gyrocal::recorder
