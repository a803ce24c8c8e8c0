#pragma once
// Builders of every message type with deterministic contents (the recorder, replay and store
// tests, the fuzz seeds), and the encoding of one message into bytes.
#include <cmath>
#include <string>
#include <vector>

#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/rate_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/status_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"

namespace gyrocal::testing {

inline constexpr int64_t kT0Utime = 1000000000000000;  // the sim rig's default start
inline constexpr int64_t kPeriodUs = 10000;            // 100 Hz

inline gyro_sample_t Gyro(const std::string& id, int64_t seq) {
    gyro_sample_t m{};
    m.utime = kT0Utime + seq * kPeriodUs;
    m.sensor_id = id;
    m.seq = seq;
    m.gyro_v = 2.5 + 1e-3 * std::sin(0.01 * static_cast<double>(seq));
    m.temp_v = 2.5 + 0.009 * (static_cast<double>(seq % 100) / 10.0);
    m.temp_c = 25.0 + static_cast<double>(seq % 100) / 10.0;
    m.supply_v = std::nan("");
    m.has_adc = false;
    m.supply_counts = -1;
    return m;
}

inline encoder_sample_t Encoder(int64_t seq) {
    encoder_sample_t m{};
    m.utime = kT0Utime + seq * kPeriodUs;
    m.encoder_id = "TABLE";
    m.seq = seq;
    m.counts = seq * 3;
    m.counts_per_rev = 40000;
    m.angle_deg = static_cast<double>(m.counts) * 360.0 / m.counts_per_rev;
    return m;
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

// A plateau over gyro seq [first, last] of `id`.
inline plateau_t Plateau(const std::string& id, const std::string& run_id, int64_t first,
                         int64_t last) {
    plateau_t m{};
    m.start_utime = kT0Utime + first * kPeriodUs;
    m.end_utime = kT0Utime + last * kPeriodUs;
    m.utime = m.end_utime;
    m.plateau_id = m.start_utime;
    m.sensor_id = id;
    m.run_id = run_id;
    m.setpoint_c = 25.0;
    m.first_seq = first;
    m.last_seq = last;
    m.n_samples = static_cast<int32_t>(last - first + 1);
    m.temp_mean_c = 25.0;
    m.gyro_mean_v = 2.5;
    m.supply_mean_v = std::nan("");
    return m;
}

inline sensitivity_point_t Sensitivity(const std::string& id, const std::string& run_id,
                                       int64_t first, int64_t last) {
    sensitivity_point_t m{};
    m.start_utime = kT0Utime + first * kPeriodUs;
    m.end_utime = kT0Utime + last * kPeriodUs;
    m.utime = m.end_utime;
    m.rotation_id = m.start_utime;
    m.sensor_id = id;
    m.run_id = run_id;
    m.first_seq = first;
    m.last_seq = last;
    m.n_samples = static_cast<int32_t>(last - first + 1);
    m.direction = 1;
    m.temp_c = 25.0;
    m.encoder_angle_deg = 90.0;
    m.sensitivity_v_per_dps = 0.0067;
    m.accepted = true;
    return m;
}

inline model_t Model(const std::string& quantity, std::vector<double> coeffs) {
    model_t m{};
    m.quantity = quantity;
    const std::vector<std::string> names = {"1", "dT", "dT^2", "dT^3"};
    for (size_t i = 0; i < coeffs.size(); ++i) m.term_names.push_back(names[i]);
    m.coeffs = coeffs;
    m.num_terms = static_cast<int16_t>(coeffs.size());
    m.covariance.assign(coeffs.size(), std::vector<double>(coeffs.size(), 0.0));
    for (size_t i = 0; i < coeffs.size(); ++i) m.covariance[i][i] = 1e-8 * (i + 1);
    m.t0_c = 25.0;
    m.temp_min_c = -10.0;
    m.temp_max_c = 60.0;
    m.residual_rms = 1e-5;
    m.n_points = 3;
    m.condition_number = 12.0;
    m.method = "wls";
    return m;
}

inline coeff_set_t Coeffs(const std::string& id, const std::string& run_id, int64_t set_id,
                          std::vector<int64_t> plateau_ids, std::vector<int64_t> rotation_ids) {
    coeff_set_t m{};
    m.utime = set_id;
    m.sensor_id = id;
    m.run_id = run_id;
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

inline rate_t Rate(const std::string& id, int64_t seq) {
    rate_t m{};
    m.utime = kT0Utime + seq * kPeriodUs;
    m.sensor_id = id;
    m.seq = seq;
    m.rate_dps = 0.01;
    m.coeff_set_id = -1;
    return m;
}

inline status_t Status(const std::string& process) {
    status_t m{};
    m.utime = 1;
    m.process = process;
    m.host = "h";
    m.state = "running";
    m.extra_names = {"x"};
    m.extra_values = {1.5};
    m.num_extra = 1;
    return m;
}

inline chamber_cmd_t ChamberCmd(const std::string& run_id) {
    chamber_cmd_t m{};
    m.utime = kT0Utime;
    m.run_id = run_id;
    m.cmd_id = 1;
    m.setpoint_c = 25;
    return m;
}

inline turntable_cmd_t TurntableCmd(const std::string& run_id) {
    turntable_cmd_t m{};
    m.utime = kT0Utime;
    m.run_id = run_id;
    m.cmd_id = 1;
    m.move_deg = 90;
    return m;
}

inline plateau_state_t PlateauState(const std::string& id) {
    plateau_state_t m{};
    m.utime = kT0Utime;
    m.sensor_id = id;
    m.state = "averaging";
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

template <class Msg>
std::vector<uint8_t> EncodeMsg(const Msg& m) {
    std::vector<uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    return b;
}

}  // namespace gyrocal::testing
