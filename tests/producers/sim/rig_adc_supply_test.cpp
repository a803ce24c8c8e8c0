// ADC quantization and the supply channel: published volts are whole codes, counts match volts,
// the supply reads nominal with its ripple and drift, and the temperature line follows the
// preset's transfer function.
#include <gtest/gtest.h>

#include <cmath>

#include "producers/sim/rig.hpp"
#include "tests/producers/sim/sim_test_support.hpp"

namespace gyrocal::sim {
namespace {

TEST(SimAdcSupply, VoltsAreWholeCodesOfTheConfiguredConverter) {
    RigConfig c = RigConfig::Defaults();
    c.num_units = 2;
    c.adc.bits = 12;  // coarse, so quantization is visible against the noise
    Rig rig(c);
    testing::RecordingSink sink;
    rig.RunUntil(c.start_utime + 60'000'000, sink);
    const double lsb = 5.0 / 4096.0;
    double supply_sum = 0.0;
    for (const GyroReading& g : sink.data.gyro) {
        ASSERT_TRUE(g.has_adc);
        ASSERT_DOUBLE_EQ(g.gyro_v, g.gyro_counts * lsb);
        ASSERT_DOUBLE_EQ(g.temp_v, g.temp_counts * lsb);
        ASSERT_DOUBLE_EQ(g.supply_v, g.supply_counts * lsb / 0.5);
        ASSERT_GE(g.gyro_counts, 0);
        ASSERT_LE(g.gyro_counts, 4095);
        // temp_c is temp_v through the preset's transfer function: 2.5 V at 25 degC, 9 mV/K
        ASSERT_NEAR(g.temp_c, 25.0 + (g.temp_v - 2.5) / 0.009, 1e-9);
        supply_sum += g.supply_v;
    }
    // The supply sits at nominal within its drift (10 mV sigma; 6 sigma) and is the same for all
    // units of one scan.
    EXPECT_NEAR(supply_sum / sink.data.gyro.size(), 5.0, 0.06);
    EXPECT_EQ(sink.data.gyro[0].supply_counts, sink.data.gyro[1].supply_counts);
}

TEST(SimAdcSupply, NoAdcMeansAnalogVoltsAndZeroCounts) {
    RigConfig c = RigConfig::Defaults();
    c.adc.bits = 0;
    Rig rig(c);
    testing::RecordingSink sink;
    rig.RunUntil(c.start_utime + 1'000'000, sink);
    for (const GyroReading& g : sink.data.gyro) {
        ASSERT_FALSE(g.has_adc);
        ASSERT_EQ(g.gyro_counts, 0);
        ASSERT_EQ(g.temp_counts, 0);
    }
}

TEST(SimAdcSupply, RippleAndDriftShowOnTheSupplyChannel) {
    RigConfig c = testing::QuietConfig();
    c.supply.ripple_v = 0.01;
    c.supply.ripple_hz = 7.0;  // below Nyquist at 100 Hz, so the samples show it as is
    Rig rig(c);
    testing::RecordingSink sink;
    rig.RunUntil(c.start_utime + 10'000'000, sink);
    double lo = 1e9, hi = -1e9;
    for (const GyroReading& g : sink.data.gyro) {
        lo = std::min(lo, g.supply_v);
        hi = std::max(hi, g.supply_v);
        ASSERT_DOUBLE_EQ(g.supply_v, sink.data.truth[&g - &sink.data.gyro[0]].supply_true_v);
    }
    // 7 Hz sampled at 100 Hz for 10 s: the extremes come within 1 - cos(pi * 7 / 100) = 2.4 %
    EXPECT_NEAR(hi - lo, 0.02, 0.02 * 0.025);
}

}  // namespace
}  // namespace gyrocal::sim
