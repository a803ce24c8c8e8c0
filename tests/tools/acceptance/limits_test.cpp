// The example limits files shipped with the project validate: tools/acceptance/limits.json
// (tools/run.sh calibrate judges by it) and strict.json.
#include "processors/acceptance/limits.hpp"

#include <gtest/gtest.h>

namespace gyrocal::acceptance {
namespace {

TEST(Limits, TheShippedExamplesValidate) {
    const Limits example = LoadLimitsFile(GYROCAL_SOURCE_DIR "/tools/acceptance/limits.json");
    EXPECT_EQ(*example.min_plateaus, 5);
    EXPECT_FALSE(example.no_unexplained_residual);
    EXPECT_TRUE(
        LoadLimitsFile(GYROCAL_SOURCE_DIR "/tools/acceptance/strict.json").no_unexplained_residual);
}

}  // namespace
}  // namespace gyrocal::acceptance
