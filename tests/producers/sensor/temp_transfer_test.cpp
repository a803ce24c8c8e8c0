// The temperature transfer: the datasheet's line, volts and degC inverse of each other, the presets
// and the refusals that name the option.
#include "producers/sensor/temp_transfer.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace gyrocal::sensor {
namespace {

TEST(TempTransfer, IsTheDatasheetLineBothWays) {
    const TempTransfer t;  // 2.5 V at 25 degC, 9 mV/K
    EXPECT_EQ(t.TempC(2.5), 25.0);
    EXPECT_EQ(t.TempV(25.0), 2.5);
    // 85 degC is 60 K above: 2.5 + 0.54 V; -40 degC 65 K below: 2.5 - 0.585 V (to rounding of the
    // products, 1e-12)
    EXPECT_NEAR(t.TempV(85.0), 3.04, 1e-12);
    EXPECT_NEAR(t.TempC(1.915), -40.0, 1e-12);
    // and each is the other's inverse over the range, to rounding (a few ulp of 100 degC)
    const TempTransfer other{1.8, 0.012};
    for (double c = -60.0; c <= 150.0; c += 0.37) {
        EXPECT_NEAR(t.TempC(t.TempV(c)), c, 1e-12);
        EXPECT_NEAR(other.TempC(other.TempV(c)), c, 1e-12);
    }
}

TEST(TempTransfer, PresetsAndRefusalsNameTheOption) {
    ASSERT_TRUE(PresetTransfer("610"));
    ASSERT_TRUE(PresetTransfer("613"));
    EXPECT_EQ(PresetTransfer("613")->v_per_c, 0.009);
    EXPECT_FALSE(PresetTransfer("612"));
    EXPECT_EQ(ValidateTransfer(TempTransfer{}), "");
    EXPECT_NE(ValidateTransfer({11.0, 0.009}).find("--temp-v-at-25c"), std::string::npos);
    EXPECT_NE(ValidateTransfer({2.5, 0.0}).find("--temp-v-per-c"), std::string::npos);
    EXPECT_NE(ValidateTransfer({2.5, NAN}).find("--temp-v-per-c"), std::string::npos);
}

}  // namespace
}  // namespace gyrocal::sensor
