// Straight-line fits: the sliding line and the prefix sums against the closed-form fit of the same
// points, and the closed form against a line known exactly.
#include "processors/numeric/line_fit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace gyrocal::numeric {
namespace {

TEST(LineFit, SlidingLineEqualsTheClosedFormFitOfItsWindow) {
    // GIVEN a long random walk (large values, so re-anchoring and cancellation are exercised)
    const double window_s = 10;
    SlidingLine line(window_s);
    std::mt19937_64 rng(9);
    std::normal_distribution<double> g(0, 0.1);
    std::vector<std::pair<int64_t, double>> all;
    double y = 1000;
    const int64_t t0 = 1'000'000'000'000'000;
    for (int k = 0; k < 20000; ++k) {
        y += g(rng);
        const int64_t t = t0 + k * 10'000 + (k % 3) * 7;  // slightly uneven sampling
        line.Add(t, y);
        all.emplace_back(t, y);
        if (k % 997 != 0 || k < 10) continue;
        std::vector<double> ts, ys;
        for (const auto& [tt, yy] : all) {
            if (t - tt <= static_cast<int64_t>(window_s * 1e6)) {
                ts.push_back((tt - t0) * 1e-6);
                ys.push_back(yy);
            }
        }
        const LineFit a = line.Fit(), b = FitLine(ts, ys);
        ASSERT_TRUE(a.ok && b.ok);
        EXPECT_EQ(a.n, b.n);
        // THEN the O(1) sums agree with the two-pass fit to rounding (relative 1e-8)
        EXPECT_NEAR(a.slope_per_s, b.slope_per_s,
                    1e-8 * (std::fabs(b.slope_per_s) + b.slope_stderr_per_s));
        EXPECT_NEAR(a.resid_std, b.resid_std, 1e-8 * b.resid_std + 1e-12);
        EXPECT_NEAR(a.value_at_last, b.value_at_last, 1e-9 * std::fabs(b.value_at_last));
    }
}

TEST(LineFit, FitLineReproducesAnExactLine) {
    // GIVEN y = 3 - 0.25 t on uneven times, no noise
    const std::vector<double> t = {0.0, 0.5, 2.0, 2.25, 7.0};
    std::vector<double> y;
    for (double ti : t) y.push_back(3.0 - 0.25 * ti);
    const LineFit f = FitLine(t, y);
    // THEN slope and value are exact to rounding (a few ulp of the values, 1e-12), no scatter
    ASSERT_TRUE(f.ok);
    EXPECT_EQ(f.n, 5);
    EXPECT_NEAR(f.slope_per_s, -0.25, 1e-12);
    EXPECT_NEAR(f.value_at_last, 3.0 - 0.25 * 7.0, 1e-12);
    EXPECT_NEAR(f.resid_std, 0.0, 1e-12);
    // and fewer than 3 points or no time span is no fit
    EXPECT_FALSE(FitLine({0.0, 1.0}, {1.0, 2.0}).ok);
    EXPECT_FALSE(FitLine({1.0, 1.0, 1.0}, {1.0, 2.0, 3.0}).ok);
}

TEST(LineFit, PrefixLineEqualsTheClosedFormFitOfEveryCentredWindow) {
    // GIVEN a noisy series on a regular grid from 0 (as the noise tracker keeps its bins)
    std::mt19937_64 rng(5);
    std::normal_distribution<double> g(0, 0.2);
    const size_t n = 400, half = 15;
    std::vector<double> t(n), y(n);
    PrefixLine prefix(n);
    for (size_t i = 0; i < n; ++i) {
        t[i] = 0.5 * static_cast<double>(i);
        y[i] = 20.0 + 0.01 * t[i] + g(rng);
        prefix.Set(i, t[i], y[i]);
    }
    for (size_t i = 0; i < n; i += 7) {
        // WHEN the window centred on i (clipped at the ends) is fitted both ways
        const size_t lo = i > half ? i - half : 0, hi = std::min(n, i + half + 1);
        const std::vector<double> ts(t.begin() + lo, t.begin() + hi);
        const std::vector<double> ys(y.begin() + lo, y.begin() + hi);
        const LineFit f = FitLine(ts, ys);
        ASSERT_TRUE(f.ok);
        // THEN slope and mean agree to rounding: the uncentred prefix sums cancel about
        // (t_max / window)^2 ~ 1e3 of their 1e-16 precision, ~1e-11 of the slope's standard
        // error here; 1e-6 of it still catches any error in the algebra
        EXPECT_NEAR(prefix.Slope(lo, hi), f.slope_per_s, 1e-6 * f.slope_stderr_per_s);
        double mean = 0;
        for (double v : ys) mean += v;
        EXPECT_NEAR(prefix.Mean(lo, hi), mean / static_cast<double>(ys.size()), 1e-12);
    }
    // and a range without spread in t has slope 0 (not a division by zero)
    PrefixLine flat(3);
    for (size_t i = 0; i < 3; ++i) flat.Set(i, 1.0, static_cast<double>(i));
    EXPECT_EQ(flat.Slope(0, 3), 0.0);
    EXPECT_EQ(flat.Mean(0, 3), 1.0);
}

}  // namespace
}  // namespace gyrocal::numeric
