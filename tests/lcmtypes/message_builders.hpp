#pragma once
// Builders of every message type with deterministic contents (the round-trip, recorder, replay
// and store tests, the fuzz seeds), and the encoding of one message into bytes.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/encoder_batch_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/flow_ack_t.hpp"
#include "gyrocal/flow_mark_t.hpp"
#include "gyrocal/gyro_batch_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/noise_t.hpp"
#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "gyrocal/rate_batch_t.hpp"
#include "gyrocal/rate_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/status_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"
#include "tests/lcmtypes/message_headers.hpp"
#include "tests/lcmtypes/test_model.hpp"

namespace gyrocal::testing {

inline constexpr int64_t kT0Utime = 1000000000000000;  // the sim rig's default start
inline constexpr int64_t kPeriodUs = 10000;            // 100 Hz

// [us] time of sample `seq` of a 100 Hz stream that starts at kT0Utime.
inline int64_t SampleUtime(int64_t seq) { return kT0Utime + seq * kPeriodUs; }

// A window over gyro seq [first, last] of unit `id`'s stream (plateau_t, sensitivity_point_t).
template <class Msg>
Msg SeqWindow(const std::string& id, const std::string& run_id, int64_t first, int64_t last) {
    Msg m = WindowOf<Msg>(id, run_id, SampleUtime(first), SampleUtime(last));
    m.first_seq = first;
    m.last_seq = last;
    m.n_samples = static_cast<int32_t>(last - first + 1);
    return m;
}

// The first order of run `run_id` to the chamber or the turntable.
template <class Cmd>
Cmd FirstOrder(const std::string& run_id) {
    Cmd m{};
    m.utime = kT0Utime;
    m.run_id = run_id;
    m.cmd_id = 1;
    return m;
}

// Sample `seq` of unit `id` at `utime` [us], read without an ADC (no codes), supply not
// measured; temp_v from temp_c by the default transfer (2.5 V at 25 degC, 9 mV/degC).
inline gyro_sample_t GyroSample(const std::string& id, int64_t utime, int64_t seq, double gyro_v,
                                double temp_c) {
    gyro_sample_t m{};
    m.utime = utime;
    m.sensor_id = id;
    m.seq = seq;
    m.gyro_v = gyro_v;
    m.temp_c = temp_c;
    m.temp_v = 2.5 + 0.009 * (temp_c - 25.0);
    m.supply_v = std::nan("");
    m.has_adc = false;
    m.supply_counts = -1;
    return m;
}

inline gyro_sample_t Gyro(const std::string& id, int64_t seq) {
    return GyroSample(id, SampleUtime(seq), seq,
                      2.5 + 1e-3 * std::sin(0.01 * static_cast<double>(seq)),
                      25.0 + static_cast<double>(seq % 100) / 10.0);
}

// The turntable's encoder at `counts` of `counts_per_rev`; angle_deg follows from them.
inline encoder_sample_t TableEncoder(int64_t utime, int64_t seq, int64_t counts,
                                     int32_t counts_per_rev) {
    encoder_sample_t m{};
    m.utime = utime;
    m.encoder_id = "TABLE";
    m.seq = seq;
    m.counts = counts;
    m.counts_per_rev = counts_per_rev;
    m.angle_deg = static_cast<double>(counts) * 360.0 / counts_per_rev;
    return m;
}

inline encoder_sample_t Encoder(int64_t seq) {
    return TableEncoder(SampleUtime(seq), seq, seq * 3, 40000);
}

inline chamber_state_t Chamber(int64_t seq) {
    chamber_state_t m{};
    m.utime = kT0Utime + seq * 1000000;
    m.seq = seq;
    m.cmd_id = 1;
    m.setpoint_c = 25.0;
    m.air_c = 24.9;
    m.at_setpoint = true;
    m.fault = "";
    return m;
}

inline run_event_t RunEvent(const std::string& run_id, const std::string& event,
                            const std::vector<std::string>& sensors) {
    run_event_t m{};
    m.utime = kT0Utime;
    m.run_id = run_id;
    m.event = event;
    m.reason = event == "stop" ? "finished" : "";
    m.setpoint_index = -1;
    m.setpoint_c = std::nan("");
    m.sensor_ids = sensors;
    m.num_sensors = static_cast<int16_t>(sensors.size());
    m.software_version = "test-1.0";
    m.config_json = R"({"setpoints_c":[0,25,50],"note":"it's \"quoted\""})";
    m.command_line = "gyrocal calibrate --sensors S01";
    m.host = "testhost";
    return m;
}

// A plateau over gyro seq [first, last] of `id` (no motion, no gaps), its gyro scattering 2 mV.
inline plateau_t Plateau(const std::string& id, const std::string& run_id, int64_t first,
                         int64_t last) {
    plateau_t m = SeqWindow<plateau_t>(id, run_id, first, last);
    m.setpoint_c = 25.0;
    m.temp_mean_c = 25.0;
    m.temp_slope_c_per_min = 0.004;
    m.gyro_mean_v = 2.5;
    m.gyro_std_v = 2e-3;
    m.gyro_sem_v = m.gyro_std_v / std::sqrt(static_cast<double>(m.n_samples));
    m.supply_mean_v = std::nan("");
    return m;
}

inline sensitivity_point_t Sensitivity(const std::string& id, const std::string& run_id,
                                       int64_t first, int64_t last) {
    sensitivity_point_t m = SeqWindow<sensitivity_point_t>(id, run_id, first, last);
    m.direction = 1;
    m.temp_c = 25.0;
    m.encoder_angle_deg = 90.0;
    m.sensitivity_v_per_dps = 0.0067;
    m.integral_v_s = m.sensitivity_v_per_dps * m.encoder_angle_deg;
    m.sensitivity_stderr_v_per_dps = 2e-6;
    m.accepted = true;
    return m;
}

// A polynomial model in dT of the test model (test_model.hpp), one term per coefficient.
inline model_t Model(const std::string& quantity, std::vector<double> coeffs) {
    model_t m{};
    m.quantity = quantity;
    const std::vector<std::string> names = {"1", "dT", "dT^2", "dT^3"};
    for (size_t i = 0; i < coeffs.size(); ++i) m.term_names.push_back(names[i]);
    m.coeffs = coeffs;
    m.num_terms = static_cast<int16_t>(coeffs.size());
    m.covariance.assign(coeffs.size(), std::vector<double>(coeffs.size(), 0.0));
    for (size_t i = 0; i < coeffs.size(); ++i) m.covariance[i][i] = 1e-8 * (i + 1);
    SetTestModelScalars(m);
    return m;
}

inline coeff_set_t Coeffs(const std::string& id, const std::string& run_id, int64_t set_id,
                          std::vector<int64_t> plateau_ids, std::vector<int64_t> rotation_ids) {
    coeff_set_t m = Stamped<coeff_set_t>(set_id, id, run_id);
    m.coeff_set_id = set_id;
    m.source = "fitter";
    m.offset = Model("offset_v", {2.5, 1e-3, -2e-5});
    m.sensitivity = Model("sensitivity_v_per_dps", {0.0067, 1e-6});
    m.plateau_ids = std::move(plateau_ids);
    m.num_plateaus = static_cast<int32_t>(m.plateau_ids.size());
    m.rotation_ids = std::move(rotation_ids);
    m.num_rotations = static_cast<int32_t>(m.rotation_ids.size());
    return m;
}

// In range, from no coefficient set yet.
inline rate_t Rate(const std::string& id, int64_t seq) {
    rate_t m{};
    m.utime = SampleUtime(seq);
    m.sensor_id = id;
    m.seq = seq;
    m.rate_dps = 0.01;
    m.angle_deg = 1e-4 * static_cast<double>(seq);  // rate_dps integrated over the samples
    m.coeff_set_id = -1;
    m.range_flag = 0;
    return m;
}

inline status_t Status(const std::string& process) {
    status_t m = FromProcess<status_t>(1, process, 4242);
    m.state = "running";
    m.decode_errors = 1;
    m.seq_gaps = 2;
    m.queue_drops = 3;
    m.rejected = 4;
    m.last_reject = "not finite";
    m.extra_names = {"x"};
    m.extra_values = {1.5};
    m.num_extra = 1;
    return m;
}

inline chamber_cmd_t ChamberCmd(const std::string& run_id) {
    chamber_cmd_t m = FirstOrder<chamber_cmd_t>(run_id);
    m.setpoint_c = 25;
    m.ramp_rate_c_per_min = 1.0;
    return m;
}

inline turntable_cmd_t TurntableCmd(const std::string& run_id) {
    turntable_cmd_t m = FirstOrder<turntable_cmd_t>(run_id);
    m.move_deg = 90;
    m.rate_dps = 30;
    m.accel_dps2 = 60;
    return m;
}

inline plateau_state_t PlateauState(const std::string& id) {
    plateau_state_t m{};
    m.utime = kT0Utime;
    m.sensor_id = id;
    m.state = "averaging";
    m.stable_for_s = 300;
    m.averaging_progress = 0.5;
    m.last_plateau_id = -1;
    return m;
}

inline power_state_t Power(const std::string& id) {
    power_state_t m{};
    m.utime = kT0Utime;
    m.sensor_id = id;
    m.power_on_utime = kT0Utime - 600 * 1000000LL;  // powered ten minutes before
    m.source = "rig";
    return m;
}

// The fitter's messages: an Allan estimate and a final report with one exclusion and one
// repeatability line (their elements travel only inside the report).
inline noise_t Noise(const std::string& id) {
    noise_t n = Stamped<noise_t>(kT0Utime, id, "R1");
    n.still_s = 600;
    n.n_segments = 2;
    n.longest_segment_s = 300;
    n.tau0_s = 0.1;
    n.arw_v_rthz = 2.4e-4;
    n.bias_instability_v = 5e-5;
    n.fit_note = "rate random walk not fitted";
    n.tau_s = {0.1, 1.0, 10.0};
    n.adev_v = {7.6e-4, 2.4e-4, 9e-5};
    n.adev_lo_v = {7.5e-4, 2.3e-4, 8e-5};
    n.adev_hi_v = {7.7e-4, 2.5e-4, 1e-4};
    n.edf = {5000, 500, 40};
    n.num_taus = 3;
    return n;
}

inline fit_report_t FitReport(const std::string& id) {
    fit_report_t r = Stamped<fit_report_t>(kT0Utime, id, "R1");
    r.coeff_set_id = 99;
    r.source = "fitter";
    r.is_final = true;
    r.status = "complete";
    r.slow_noise_v = 7e-5;
    r.slow_noise_dps = 0.012;
    r.slow_noise_source = "Allan deviation of this run (NOISE_" + id + ")";
    fit_exclusion_t x{};
    x.kind = "plateau";
    x.item_id = 20;
    x.reason = "leave-one-out";
    r.excluded = {x};
    r.num_excluded = 1;
    repeatability_t rep{};
    rep.first_plateau_id = 10;
    rep.second_plateau_id = 30;
    rep.first_approach = 0;
    rep.second_approach = -1;
    rep.verdict = "repeatable within 3 sigma";
    r.repeats = {rep};
    r.num_repeats = 1;
    return r;
}

// Samples seq first..first+n-1 of one unit in one message (bus/batch.hpp's batch forms), each
// made by sample(seq); the batch's time is its newest sample's (0 when empty), its sensor id `id`
// where the batch type has one (also when empty).
template <class Batch, class Sample>
Batch BatchOf(const std::string& id, int64_t first, int n, Sample sample) {
    Batch b{};
    for (int i = 0; i < n; ++i) b.samples.push_back(sample(first + i));
    b.num_samples = n;
    b.utime = n > 0 ? b.samples.back().utime : 0;
    if constexpr (requires { b.sensor_id; }) b.sensor_id = id;
    return b;
}

inline gyro_batch_t GyroBatch(const std::string& id, int64_t first, int n) {
    return BatchOf<gyro_batch_t>(id, first, n, [&](int64_t seq) { return Gyro(id, seq); });
}

inline encoder_batch_t EncoderBatch(int64_t first, int n) {
    return BatchOf<encoder_batch_t>("", first, n, [](int64_t seq) { return Encoder(seq); });
}

inline rate_batch_t RateBatch(const std::string& id, int64_t first, int n) {
    return BatchOf<rate_batch_t>(id, first, n, [&](int64_t seq) { return Rate(id, seq); });
}

inline flow_mark_t FlowMark(int64_t mark_seq) {
    flow_mark_t m = FromProcess<flow_mark_t>(1, "gyrocal-csv-source", 4243);
    m.mark_seq = mark_seq;
    m.published = 100 * mark_seq;
    m.data_utime = SampleUtime(mark_seq);
    return m;
}

inline flow_ack_t FlowAck(int64_t mark_seq) {
    flow_ack_t m = FromProcess<flow_ack_t>(2, "gyrocal-recorder", 4242);
    m.source_host = "h";
    m.source_pid = 4243;
    m.mark_seq = mark_seq;
    m.leaving = false;
    return m;
}

// Throws std::logic_error when the encoding is not the size the message announced.
template <class Msg>
std::vector<uint8_t> EncodeMsg(const Msg& m) {
    std::vector<uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
    if (m.encode(b.data(), 0, static_cast<int>(b.size())) != static_cast<int>(b.size())) {
        throw std::logic_error(std::string("encoding a ") + Msg::getTypeName() +
                               " wrote another size than it announced");
    }
    return b;
}

}  // namespace gyrocal::testing
