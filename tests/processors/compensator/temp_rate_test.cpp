#include "compensator/temp_rate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace gyrocal::compensate {
namespace {

// Ramp of 1 degC/min sampled at 100 Hz with temperature noise sigma = 0.01 degC. Over a 10 s
// window (N = 1001 samples) the least-squares slope has sd sigma / sqrt(sum (t - tbar)^2) =
// 0.01 / sqrt(N W^2 / 12) = 1.1e-4 degC/s; tolerance 4 sd = 4.4e-4 degC/s.
TEST(TempRateEstimator, SlopeOfANoisyRampWithinFourSigma) {
    TempRateEstimator est(10.0);
    std::mt19937_64 rng(4);
    std::normal_distribution<double> noise(0, 0.01);
    const double slope = 1.0 / 60.0;
    const double tol = 4 * 0.01 / std::sqrt(1001 * 100.0 / 12.0);
    for (int k = 0; k < 6000; ++k) {
        const double ts = 0.01 * k;
        est.Add(1'000'000'000'000'000 + k * 10'000, 20.0 + slope * ts + noise(rng));
        if (k < 400) {
            EXPECT_TRUE(std::isnan(est.rate_c_per_s())) << k;  // less than half a window
        }
        if (k > 1000 && k % 500 == 0) {
            EXPECT_NEAR(est.rate_c_per_s(), slope, tol) << k;
        }
    }
    EXPECT_EQ(est.heating(), 1.0);
}

TEST(TempRateEstimator, BranchFollowsClearSlopesAndHoldsOnAPlateau) {
    TempRateEstimator est(10.0);
    int64_t k = 0;
    auto run = [&](double seconds, double slope_c_per_s, double& temp) {
        for (int i = 0; i < seconds * 100; ++i, ++k) {
            temp += slope_c_per_s * 0.01;
            est.Add(k * 10'000, temp);
        }
    };
    double temp = 25;
    run(30, -1.0 / 60, temp);
    EXPECT_EQ(est.heating(), -1.0);
    run(60, 0.0, temp);  // plateau reached while cooling: still the cooling branch
    EXPECT_EQ(est.heating(), -1.0);
    // running sums cancel to ~eps * sum(t*T) / sum((t-tbar)^2) ~ 1e-11 degC/s; 1e-9 is still far
    // below the 1.7e-3 degC/s branch deadband.
    EXPECT_NEAR(est.rate_c_per_s(), 0.0, 1e-9);
    run(30, 2.0 / 60, temp);
    EXPECT_EQ(est.heating(), 1.0);
}

TEST(TempRateEstimator, LongRunsKeepTheirPrecision) {
    // After 3 simulated hours the origin has moved; a noise-free ramp still gives its slope.
    TempRateEstimator est(10.0);
    const double slope = 0.5 / 60;
    for (int64_t k = 0; k < 3 * 3600 * 10; ++k)
        est.Add(k * 100'000, -10 + slope * 0.1 * k);  // 10 Hz
    EXPECT_NEAR(est.rate_c_per_s(), slope, 1e-10);
}

}  // namespace
}  // namespace gyrocal::compensate
