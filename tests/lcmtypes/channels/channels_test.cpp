// Channel names: per-sensor names, their validation, and the sensor id back from a channel.
#include "lcmtypes/channels/channels.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <stdexcept>
#include <string>

namespace gyrocal {
namespace {

TEST(Channels, PerSensorNamesAndValidation) {
    EXPECT_EQ(channels::Gyro("S01"), "GYRO_S01");
    EXPECT_EQ(channels::Coeffs("a-b_c"), "COEFFS_a-b_c");
    EXPECT_THROW(channels::Gyro(""), std::invalid_argument);
    EXPECT_THROW(channels::Gyro("S 1"), std::invalid_argument);
    EXPECT_THROW(channels::Gyro("S.*"), std::invalid_argument);
    EXPECT_THROW(channels::Gyro(std::string(33, 'a')), std::invalid_argument);
    EXPECT_EQ(channels::SensorOf(channels::kGyroPrefix, "GYRO_S09"), "S09");
    EXPECT_EQ(channels::SensorOf(channels::kGyroPrefix, "RATE_S09"), std::nullopt);
    EXPECT_EQ(channels::SensorOf(channels::kGyroPrefix, "GYRO_"), std::nullopt);
}

}  // namespace
}  // namespace gyrocal
