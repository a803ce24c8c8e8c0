// Thermal physics: chamber ramp limit and settling, package lag, temperature-sensor lag.
// The thermal chain is deterministic when the noises are off, so tolerances here are set by the
// discretisation (exact zero-order-hold steps of 10 ms: relative errors ~1e-6) and by the stated
// transients; each is given beside its check.
#include <gtest/gtest.h>

#include <cmath>

#include "producers/sim/rig.hpp"
#include "tests/producers/sim/sim_test_support.hpp"

namespace gyrocal::sim {
namespace {

// Least-squares slope of ln(dev) against t over samples with t in [t0, t1].
double LogSlope(const std::vector<double>& t, const std::vector<double>& dev, double t0,
                double t1) {
    double n = 0, st = 0, sy = 0, stt = 0, sty = 0;
    for (size_t i = 0; i < t.size(); ++i) {
        if (t[i] < t0 || t[i] > t1) continue;
        const double y = std::log(dev[i]);
        n += 1;
        st += t[i];
        sy += y;
        stt += t[i] * t[i];
        sty += t[i] * y;
    }
    return (n * sty - st * sy) / (n * stt - st * st);
}

// First time at which dev falls below `level`.
double CrossingTime(const std::vector<double>& t, const std::vector<double>& dev, double level) {
    for (size_t i = 1; i < t.size(); ++i) {
        if (dev[i] < level) {  // linear interpolation between the two samples
            return t[i - 1] + (t[i] - t[i - 1]) * (dev[i - 1] - level) / (dev[i - 1] - dev[i]);
        }
    }
    return NAN;
}

TEST(SimThermal, StepResponseMeasuresConfiguredLags) {
    // GIVEN a chamber that steps almost instantly (1000 degC/min, 0.5 s settling), a package lag
    // of 100 s and a sensor lag of 15 s, no noise and no ADC
    RigConfig c = testing::QuietConfig();
    c.thermal.ramp_c_per_min = 1000.0;
    c.thermal.air_tau_s = 0.5;
    c.thermal.package_tau_s = 100.0;
    c.spread.package_tau_spread_frac = 0.0;
    c.thermal.sensor_tau_s = 15.0;
    Rig rig(c);
    ASSERT_TRUE(rig.ChamberCommand(1, 35.0, 0.0).accepted);
    testing::RecordingSink sink;
    // WHEN 3000 s (30 package lags) are simulated
    rig.RunUntil(c.start_utime + 3'000'000'000LL, sink);
    const auto& g = sink.data.gyro;
    const auto& tr = sink.data.truth;
    const double final_temp_c = g.back().temp_c;  // includes the unit's sensor offset
    std::vector<double> t, die_dev, sensor_dev, air_dev;
    for (size_t i = 0; i < g.size(); ++i) {
        t.push_back((g[i].utime - c.start_utime) * 1e-6);
        die_dev.push_back(35.0 - tr[i].die_c);
        sensor_dev.push_back(final_temp_c - g[i].temp_c);
        air_dev.push_back(35.0 - tr[i].air_c);
    }
    // THEN the measured temperature (temp_c) decays with the package time constant: after
    // 6 sensor lags the sensor's own mode is below e^-6 of the package mode.
    const double tau_measured = -1.0 / LogSlope(t, sensor_dev, 100.0, 600.0);
    EXPECT_NEAR(tau_measured, 100.0, 100.0 * 0.005);
    EXPECT_NEAR(-1.0 / LogSlope(t, die_dev, 50.0, 600.0), 100.0, 100.0 * 1e-4);
    // and the sensor reading lags the die by tau_p ln(tau_p / (tau_p - tau_s)) = 16.25 s at late
    // times (two-pole response), which in turn lags the air.
    const double shift = CrossingTime(t, sensor_dev, 1.0) - CrossingTime(t, die_dev, 1.0);
    EXPECT_NEAR(shift, 100.0 * std::log(100.0 / 85.0), 0.2);
    for (size_t i = 100; i < g.size() && t[i] < 1000.0; i += 1000) {  // before rounding level
        ASSERT_LT(air_dev[i], die_dev[i]) << "t " << t[i];
        ASSERT_LT(die_dev[i], sensor_dev[i]) << "t " << t[i];
    }
    // and the reported temperature ends at the die's plus the unit's sensor offset (truth)
    EXPECT_NEAR(final_temp_c, 35.0 + rig.units()[0].temp_sensor_offset_c, 1e-6);
}

TEST(SimThermal, ChamberRampsAtItsLimitAndReportsAtSetpointAtOneHertz) {
    RigConfig c = testing::QuietConfig();
    c.thermal.ramp_c_per_min = 3.0;
    c.thermal.air_tau_s = 30.0;
    Rig rig(c);
    // A faster request is capped to the chamber's own 3 degC/min.
    ASSERT_TRUE(rig.ChamberCommand(4, 40.0, 10.0).accepted);
    testing::RecordingSink sink;
    rig.RunUntil(c.start_utime + 900'000'000LL, sink);
    const auto& ch = sink.data.chamber;
    ASSERT_EQ(ch.size(), 901u);  // t = 0 .. 900 s at 1 Hz
    for (size_t i = 1; i < ch.size(); ++i) {
        ASSERT_EQ(ch[i].utime - ch[i - 1].utime, 1'000'000);
        ASSERT_EQ(ch[i].seq, ch[i - 1].seq + 1);
        ASSERT_LE(ch[i].air_c - ch[i - 1].air_c, 3.0 / 60.0 + 1e-12) << "ramp limit";
        ASSERT_EQ(ch[i].cmd_id, 4);
        ASSERT_DOUBLE_EQ(ch[i].setpoint_c, 40.0);
    }
    // Reference reaches 40 at 300 s; the air lags it by air_tau (30 s) at 3 degC/min = 1.5 degC,
    // so it is within 0.5 degC at 300 + 30 ln(1.5/0.5) = 333 s (+- one 1 Hz report).
    size_t first = 0;
    while (first < ch.size() && !ch[first].at_setpoint) ++first;
    EXPECT_NEAR(static_cast<double>(first), 300.0 + 30.0 * std::log(3.0), 1.5);
    EXPECT_NEAR(ch.back().air_c, 40.0, 1e-3);
}

TEST(SimThermal, AllUnitsShareTheChamberButLagByTheirOwnPackage) {
    RigConfig c = testing::QuietConfig();
    c.num_units = 4;
    c.thermal.ramp_c_per_min = 30.0;
    Rig rig(c);
    rig.ChamberCommand(1, 60.0, 0.0);
    testing::RecordingSink sink;
    rig.RunUntil(c.start_utime + 300'000'000LL, sink);
    const size_t n = sink.data.gyro.size();
    std::vector<double> die(4);
    for (size_t i = n - 4; i < n; ++i) {
        EXPECT_DOUBLE_EQ(sink.data.truth[i].air_c, sink.data.truth[n - 1].air_c);
        die[sink.data.gyro[i].unit_index] = sink.data.truth[i].die_c;
    }
    // Package lags differ per unit (5 % spread), so die temperatures differ mid-transient.
    EXPECT_NE(die[0], die[1]);
    for (int u = 0; u < 4; ++u) EXPECT_GT(rig.units()[u].package_tau_s, 0.0);
}

}  // namespace
}  // namespace gyrocal::sim
