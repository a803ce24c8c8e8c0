// Turntable profile, encoder quantization, the gyro's view of a move, saturation and refusals.
// The table and encoder are exact functions of time and noise-free; tolerances are one encoder
// count or floating-point rounding unless stated.
#include "producers/sim/turntable.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "producers/sim/rig.hpp"
#include "tests/producers/sim/sim_test_support.hpp"

namespace gyrocal::sim {
namespace {

TEST(SimTurntable, TrapezoidAndTriangleProfiles) {
    TableMove m;
    m.distance_deg = 90.0;
    m.rate_dps = 30.0;
    m.accel_dps2 = 60.0;
    // d/v + v/a = 3 + 0.5 s; cruise reached at 0.5 s
    EXPECT_DOUBLE_EQ(m.Duration(), 3.5);
    double p, r;
    m.At(0.25, p, r);
    EXPECT_DOUBLE_EQ(r, 15.0);
    EXPECT_DOUBLE_EQ(p, 0.5 * 60.0 * 0.25 * 0.25);
    m.At(2.0, p, r);
    EXPECT_DOUBLE_EQ(r, 30.0);
    m.At(3.5, p, r);
    EXPECT_DOUBLE_EQ(p, 90.0);
    EXPECT_DOUBLE_EQ(r, 0.0);
    // Too short to reach cruise: triangle with peak sqrt(d a)
    TableMove t = m;
    t.distance_deg = -5.0;
    EXPECT_DOUBLE_EQ(t.Duration(), 2.0 * std::sqrt(5.0 / 60.0));
    t.At(t.Duration() / 2, p, r);
    EXPECT_NEAR(r, -std::sqrt(5.0 * 60.0), 1e-12);
    EXPECT_NEAR(p, -2.5, 1e-12);
}

TEST(SimTurntable, EncoderCountsQuantizeAndNinetyDegreesEndWithinOneCount) {
    RigConfig c = testing::QuietConfig();
    c.encoder.lines_per_rev = 1000;
    c.encoder.quadrature = 4;
    c.encoder.rate_hz = 250.0;
    Rig rig(c);
    testing::RecordingSink sink;
    rig.RunUntil(c.start_utime + 1'000'000, sink);
    ASSERT_TRUE(rig.TurntableCommand(1, 90.0, 0.0, 0.0).accepted);
    rig.RunUntil(c.start_utime + 10'000'000, sink);
    ASSERT_TRUE(rig.TurntableCommand(2, 360.0, 90.0, 180.0).accepted);
    rig.RunUntil(c.start_utime + 20'000'000, sink);
    const auto& e = sink.data.encoder;
    const double count_deg = 360.0 / 4000.0;
    for (size_t i = 0; i < e.size(); ++i) {
        ASSERT_EQ(e[i].counts_per_rev, 4000);
        // Published angle is exactly counts * 360 / cpr, within one count below the true angle.
        ASSERT_DOUBLE_EQ(e[i].angle_deg, e[i].counts * count_deg);
        ASSERT_GT(e[i].true_angle_deg - e[i].angle_deg, -count_deg) << i;
        ASSERT_LT(e[i].true_angle_deg - e[i].angle_deg, count_deg + 1e-9) << i;
        if (i > 0) {
            ASSERT_EQ(e[i].utime - e[i - 1].utime, 4000) << "250 Hz";
        }
    }
    const EncoderReading start = e.front();
    const EncoderReading after_90 = e[static_cast<size_t>(9.0 * 250)];
    const EncoderReading after_rev = e.back();
    EXPECT_NEAR(after_90.angle_deg - start.angle_deg, 90.0, count_deg);
    EXPECT_LE(std::llabs(after_90.counts - start.counts - 1000), 1);
    // One revolution = counts_per_rev counts (the seeded phase cancels in a difference).
    EXPECT_EQ(after_rev.counts - after_90.counts, 4000);
    EXPECT_DOUBLE_EQ(after_rev.true_angle_deg, 450.0);
}

TEST(SimTurntable, GyroSeesTheMoveAndSaturatesBeyondRange) {
    // GIVEN a noise-free 613 unit (+-150 deg/s) and a move at 170 deg/s
    RigConfig c = testing::QuietConfig();
    c.preset = PresetByName("613");
    c.noise.lpf_hz = 0.0;
    Rig rig(c);
    testing::RecordingSink sink;
    rig.RunUntil(c.start_utime, sink);
    ASSERT_TRUE(rig.TurntableCommand(1, 720.0, 170.0, 400.0).accepted);
    rig.RunUntil(c.start_utime + 8'000'000, sink);
    double integral_deg = 0.0;
    double max_rate = 0.0;
    for (size_t i = 0; i < sink.data.gyro.size(); ++i) {
        const GyroTruth& t = sink.data.truth[i];
        const double rate = (sink.data.gyro[i].gyro_v - t.offset_v) / t.sensitivity_v_per_dps;
        integral_deg += rate * 0.01;
        max_rate = std::max(max_rate, rate);
    }
    // THEN the output clips at the range limit during cruise (rate exact to rounding)
    EXPECT_NEAR(max_rate, 150.0, 1e-6);
    // and the integral falls short of 720 deg by the clipped part: cruise 170 deg/s for
    // 720/170 - 170/400 s, clipped by 20 deg/s, plus the ramps above 150 (2 * 20^2/(2*400) s*deg/s)
    const double cruise_s = 720.0 / 170.0 - 170.0 / 400.0;
    const double lost_deg = 20.0 * cruise_s + 2.0 * 20.0 * 20.0 / (2.0 * 400.0);
    // Rectangle-rule integration of a piecewise-linear rate at 100 Hz: error below 0.1 deg.
    EXPECT_NEAR(integral_deg, 720.0 - lost_deg, 0.1);
}

TEST(SimTurntable, ImpossibleOrdersAreRefusedAndReported) {
    RigConfig c = testing::QuietConfig();
    Rig rig(c);
    const CommandResult fast = rig.TurntableCommand(1, 90.0, 500.0, 0.0);
    EXPECT_FALSE(fast.accepted);
    EXPECT_NE(fast.reason.find("rate_dps"), std::string::npos) << fast.reason;
    EXPECT_FALSE(rig.TurntableCommand(2, NAN, 0.0, 0.0).accepted);
    EXPECT_FALSE(rig.TurntableCommand(3, 1e9, 0.0, 0.0).accepted);
    EXPECT_FALSE(rig.TurntableCommand(4, 90.0, 0.0, 1e6).accepted);
    EXPECT_FALSE(rig.table_busy()) << "a refused order queues nothing";
    const CommandResult hot = rig.ChamberCommand(5, 150.0, 0.0);
    EXPECT_FALSE(hot.accepted);
    EXPECT_NE(hot.reason.find("-45"), std::string::npos) << "says the valid range: " << hot.reason;
    EXPECT_FALSE(rig.ChamberCommand(6, NAN, 0.0).accepted);
    testing::RecordingSink sink;
    rig.RunUntil(c.start_utime, sink);
    ASSERT_EQ(sink.data.chamber.size(), 1u);
    EXPECT_EQ(sink.data.chamber[0].cmd_id, -1);
    EXPECT_DOUBLE_EQ(sink.data.chamber[0].setpoint_c, c.thermal.start_temp_c);
    EXPECT_FALSE(sink.data.chamber[0].fault.empty());
    // An accepted order clears the fault.
    EXPECT_TRUE(rig.ChamberCommand(7, 30.0, 0.0).accepted);
    rig.RunUntil(c.start_utime + 1'000'000, sink);
    EXPECT_TRUE(sink.data.chamber.back().fault.empty());
    EXPECT_EQ(sink.data.chamber.back().cmd_id, 7);
}

}  // namespace
}  // namespace gyrocal::sim
