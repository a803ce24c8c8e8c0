// Every message type survives encode -> decode with non-default values in every field, and a
// payload of one type does not decode as another (the fingerprint check the Bus relies on).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/rate_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/status_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"
#include "message_builders.hpp"

namespace gyrocal {
namespace {

template <class Msg>
Msg RoundTrip(const Msg& in) {
    std::vector<uint8_t> buf(static_cast<size_t>(in.getEncodedSize()));
    EXPECT_EQ(in.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
    Msg out;
    EXPECT_EQ(out.decode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
    return out;
}

// The shared builder's quadratic, with a full covariance and figures of its own.
model_t MakeModel(const std::string& quantity, double scale) {
    model_t m = testing::Model(quantity, {2.5 * scale, 1e-3 * scale, -2e-6 * scale});
    m.covariance = {{1e-10, 1e-12, 0}, {1e-12, 1e-12, -1e-15}, {0, -1e-15, 1e-16}};
    m.residual_rms = 3.3e-5;
    m.n_points = 5;
    m.condition_number = 12.5;
    return m;
}

TEST(RoundTrip, GyroSample) {
    gyro_sample_t m;
    m.utime = 1'000'000'123'456;
    m.sensor_id = "S07";
    m.seq = 987654321;
    m.gyro_v = 2.512345;
    m.temp_v = 2.48;
    m.temp_c = 22.7;
    m.supply_v = 5.01;
    m.has_adc = true;
    m.gyro_counts = 32767;
    m.temp_counts = -12;
    m.supply_counts = 65535;
    gyro_sample_t r = RoundTrip(m);
    EXPECT_EQ(r.utime, m.utime);
    EXPECT_EQ(r.sensor_id, m.sensor_id);
    EXPECT_EQ(r.seq, m.seq);
    EXPECT_EQ(r.gyro_v, m.gyro_v);
    EXPECT_EQ(r.temp_v, m.temp_v);
    EXPECT_EQ(r.temp_c, m.temp_c);
    EXPECT_EQ(r.supply_v, m.supply_v);
    EXPECT_EQ(r.has_adc, m.has_adc);
    EXPECT_EQ(r.gyro_counts, m.gyro_counts);
    EXPECT_EQ(r.temp_counts, m.temp_counts);
    EXPECT_EQ(r.supply_counts, m.supply_counts);
}

TEST(RoundTrip, GyroSampleKeepsNaNSupply) {
    gyro_sample_t m;
    m.sensor_id = "S01";
    m.supply_v = std::nan("");
    EXPECT_TRUE(std::isnan(RoundTrip(m).supply_v));
}

TEST(RoundTrip, EncoderSample) {
    encoder_sample_t m;
    m.utime = 42;
    m.encoder_id = "TABLE";
    m.seq = 7;
    m.counts = -5000;
    m.counts_per_rev = 20000;
    m.angle_deg = -90.0;
    encoder_sample_t r = RoundTrip(m);
    EXPECT_EQ(r.utime, 42);
    EXPECT_EQ(r.encoder_id, "TABLE");
    EXPECT_EQ(r.seq, 7);
    EXPECT_EQ(r.counts, -5000);
    EXPECT_EQ(r.counts_per_rev, 20000);
    EXPECT_EQ(r.angle_deg, -90.0);
}

TEST(RoundTrip, ChamberCmdAndState) {
    chamber_cmd_t c;
    c.utime = 5;
    c.run_id = "run-1";
    c.cmd_id = 3;
    c.setpoint_c = -10.0;
    c.ramp_rate_c_per_min = 2.5;
    chamber_cmd_t rc = RoundTrip(c);
    EXPECT_EQ(rc.run_id, "run-1");
    EXPECT_EQ(rc.cmd_id, 3);
    EXPECT_EQ(rc.setpoint_c, -10.0);
    EXPECT_EQ(rc.ramp_rate_c_per_min, 2.5);

    chamber_state_t s;
    s.utime = 6;
    s.seq = 11;
    s.cmd_id = 3;
    s.setpoint_c = -10.0;
    s.air_c = -9.5;
    s.at_setpoint = true;
    s.fault = "setpoint 200 C outside -45..90 C";
    chamber_state_t rs = RoundTrip(s);
    EXPECT_EQ(rs.seq, 11);
    EXPECT_EQ(rs.cmd_id, 3);
    EXPECT_EQ(rs.air_c, -9.5);
    EXPECT_TRUE(rs.at_setpoint);
    EXPECT_EQ(rs.fault, s.fault);
}

TEST(RoundTrip, TurntableCmd) {
    turntable_cmd_t m;
    m.utime = 9;
    m.run_id = "r";
    m.cmd_id = 2;
    m.move_deg = -90.0;
    m.rate_dps = 30.0;
    m.accel_dps2 = 60.0;
    turntable_cmd_t r = RoundTrip(m);
    EXPECT_EQ(r.cmd_id, 2);
    EXPECT_EQ(r.move_deg, -90.0);
    EXPECT_EQ(r.rate_dps, 30.0);
    EXPECT_EQ(r.accel_dps2, 60.0);
}

TEST(RoundTrip, RunEvent) {
    run_event_t m;
    m.utime = 10;
    m.run_id = "2026-11-21T05:00:00Z-abc";
    m.event = "start";
    m.reason = "operator";
    m.setpoint_index = 2;
    m.setpoint_c = 60.0;
    m.sensor_ids = {"S01", "S02"};
    m.num_sensors = 2;
    m.software_version = "v0.1-3-gabc";
    m.config_json = R"({"profile":[-10,30,60]})";
    m.command_line = "gyrocal calibrate";
    m.host = "lab-pc";
    run_event_t r = RoundTrip(m);
    EXPECT_EQ(r.run_id, m.run_id);
    EXPECT_EQ(r.event, "start");
    EXPECT_EQ(r.setpoint_index, 2);
    EXPECT_EQ(r.sensor_ids, m.sensor_ids);
    EXPECT_EQ(r.config_json, m.config_json);
    EXPECT_EQ(r.host, "lab-pc");
}

TEST(RoundTrip, Plateau) {
    plateau_t m;
    m.utime = 100;
    m.sensor_id = "S02";
    m.run_id = "r";
    m.plateau_id = 40;
    m.setpoint_c = 30.0;
    m.start_utime = 40;
    m.end_utime = 100;
    m.first_seq = 4;
    m.last_seq = 10;
    m.n_samples = 6000;
    m.n_excluded_motion = 12;
    m.seq_gaps = 1;
    m.temp_mean_c = 29.9;
    m.temp_std_c = 0.02;
    m.temp_sem_c = 0.001;
    m.temp_slope_c_per_min = 0.004;
    m.gyro_mean_v = 2.51;
    m.gyro_std_v = 0.002;
    m.gyro_sem_v = 0.0001;
    m.temp_mean_v = 2.545;
    m.supply_mean_v = 5.0;
    plateau_t r = RoundTrip(m);
    EXPECT_EQ(r.plateau_id, 40);
    EXPECT_EQ(r.n_samples, 6000);
    EXPECT_EQ(r.n_excluded_motion, 12);
    EXPECT_EQ(r.seq_gaps, 1);
    EXPECT_EQ(r.temp_slope_c_per_min, 0.004);
    EXPECT_EQ(r.gyro_sem_v, 0.0001);
    EXPECT_EQ(r.supply_mean_v, 5.0);
}

TEST(RoundTrip, PlateauState) {
    plateau_state_t m;
    m.utime = 1;
    m.sensor_id = "S03";
    m.state = "settling";
    m.temp_c = 12.0;
    m.temp_slope_c_per_min = 0.3;
    m.temp_std_c = 0.01;
    m.stable_for_s = 12.5;
    m.averaging_progress = 0.25;
    m.last_plateau_id = -1;
    plateau_state_t r = RoundTrip(m);
    EXPECT_EQ(r.state, "settling");
    EXPECT_EQ(r.stable_for_s, 12.5);
    EXPECT_EQ(r.averaging_progress, 0.25);
    EXPECT_EQ(r.last_plateau_id, -1);
}

TEST(RoundTrip, SensitivityPoint) {
    sensitivity_point_t m;
    m.utime = 3;
    m.sensor_id = "S04";
    m.run_id = "r";
    m.rotation_id = 77;
    m.start_utime = 77;
    m.end_utime = 99;
    m.first_seq = 1;
    m.last_seq = 2;
    m.n_samples = 300;
    m.direction = -1;
    m.temp_c = 59.8;
    m.encoder_angle_deg = -90.0;
    m.offset_v = 2.49;
    m.offset_stderr_v = 1e-5;
    m.integral_v_s = -0.54;
    m.sensitivity_v_per_dps = 0.006;
    m.sensitivity_stderr_v_per_dps = 2e-6;
    m.accepted = false;
    m.reject_reason = "sequence gap inside the move";
    sensitivity_point_t r = RoundTrip(m);
    EXPECT_EQ(r.direction, -1);
    EXPECT_EQ(r.integral_v_s, -0.54);
    EXPECT_EQ(r.sensitivity_stderr_v_per_dps, 2e-6);
    EXPECT_FALSE(r.accepted);
    EXPECT_EQ(r.reject_reason, m.reject_reason);
}

TEST(RoundTrip, CoeffSetWithNestedModelsAndCovariance) {
    coeff_set_t m;
    m.utime = 1234;
    m.sensor_id = "S01";
    m.run_id = "r";
    m.coeff_set_id = 1234;
    m.source = "analysis:7";
    m.offset = MakeModel("offset_v", 1.0);
    m.sensitivity = MakeModel("sensitivity_v_per_dps", 0.0024);
    m.plateau_ids = {10, 20, 30};
    m.num_plateaus = 3;
    m.rotation_ids = {11, 12};
    m.num_rotations = 2;
    coeff_set_t r = RoundTrip(m);
    EXPECT_EQ(r.source, "analysis:7");
    EXPECT_EQ(r.offset.term_names, m.offset.term_names);
    EXPECT_EQ(r.offset.coeffs, m.offset.coeffs);
    EXPECT_EQ(r.offset.covariance, m.offset.covariance);
    EXPECT_EQ(r.sensitivity.coeffs, m.sensitivity.coeffs);
    EXPECT_EQ(r.sensitivity.quantity, "sensitivity_v_per_dps");
    EXPECT_EQ(r.offset.condition_number, 12.5);
    EXPECT_EQ(r.plateau_ids, m.plateau_ids);
    EXPECT_EQ(r.rotation_ids, m.rotation_ids);
}

TEST(RoundTrip, Rate) {
    rate_t m;
    m.utime = 8;
    m.sensor_id = "S01";
    m.seq = 5;
    m.rate_dps = -0.013;
    m.angle_deg = 0.5;
    m.temp_c = 70.0;
    m.coeff_set_id = 1234;
    m.range_flag = 2;
    rate_t r = RoundTrip(m);
    EXPECT_EQ(r.rate_dps, -0.013);
    EXPECT_EQ(r.angle_deg, 0.5);
    EXPECT_EQ(r.coeff_set_id, 1234);
    EXPECT_EQ(r.range_flag, 2);
}

TEST(RoundTrip, Status) {
    status_t m;
    m.utime = 1;
    m.process = "gyrocal-fitter";
    m.host = "h";
    m.pid = 4242;
    m.state = "refused";
    m.received = 10;
    m.published = 2;
    m.decode_errors = 3;
    m.seq_gaps = 4;
    m.queue_drops = 5;
    m.rejected = 6;
    m.last_reject = "range 10 C narrower than 20 C";
    m.extra_names = {"points"};
    m.extra_values = {3.0};
    m.num_extra = 1;
    status_t r = RoundTrip(m);
    EXPECT_EQ(r.pid, 4242);
    EXPECT_EQ(r.decode_errors, 3);
    EXPECT_EQ(r.seq_gaps, 4);
    EXPECT_EQ(r.queue_drops, 5);
    EXPECT_EQ(r.rejected, 6);
    EXPECT_EQ(r.last_reject, m.last_reject);
    EXPECT_EQ(r.extra_names, m.extra_names);
    EXPECT_EQ(r.extra_values, m.extra_values);
}

TEST(Fingerprint, PayloadOfOneTypeDoesNotDecodeAsAnother) {
    gyro_sample_t g;
    g.sensor_id = "S01";
    std::vector<uint8_t> buf = testing::EncodeMsg(g);
    encoder_sample_t e;
    EXPECT_LT(e.decode(buf.data(), 0, static_cast<int>(buf.size())), 0);
    rate_t r;
    EXPECT_LT(r.decode(buf.data(), 0, static_cast<int>(buf.size())), 0);
}

}  // namespace
}  // namespace gyrocal
