// The distribution functions behind the significance tests (numeric/distributions.hpp) against
// tabulated values.
#include "processors/numeric/distributions.hpp"

#include <gtest/gtest.h>

namespace gyrocal::numeric {
namespace {

TEST(Distributions, QuantilesMatchTabulatedValues) {
    // Tables (Abramowitz & Stegun 26.x; any statistics text): z_0.975 = 1.959964,
    // t_10 two-sided 0.05 = 2.228139, F(2, 10) upper 0.05 = 4.102821, chi2_1 0.95 = 3.841459,
    // chi2_10 median = 9.341818.
    EXPECT_NEAR(TwoSidedTQuantile(0.05, 0), 1.959964, 1e-5);
    EXPECT_NEAR(TwoSidedTQuantile(0.05, 10), 2.228139, 1e-5);
    EXPECT_NEAR(FUpperQuantile(0.05, 2, 10), 4.102821, 1e-5);
    EXPECT_NEAR(ChiSquareQuantile(0.95, 1), 3.841459, 1e-5);
    EXPECT_NEAR(ChiSquareQuantile(0.5, 10), 9.341818, 1e-5);
    EXPECT_NEAR(FUpperTail(4.102821, 2, 10), 0.05, 1e-6);
    EXPECT_NEAR(ChiSquareLowerTail(3.841459, 1), 0.95, 1e-6);
}

}  // namespace
}  // namespace gyrocal::numeric
