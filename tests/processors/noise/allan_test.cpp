// The Allan deviation library and the per-unit tracker (processors/noise) against series of
// known noise: white (closed form), and othersim's OU-bank flicker (its own theory), plus the
// tracker's stretch and quiet-segment rules.
#include "processors/noise/allan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "processors/noise/noise_tracker.hpp"
#include "tests/processors/numeric/synthetic_noise.hpp"
#include "tests/processors/validate_check.hpp"
#include "tests/support/othersim/physics.hpp"

namespace gyrocal::noise {
namespace {

// White noise of sigma per sample at 100 Hz: AVAR(tau) = sigma^2 tau0 / tau exactly (tau0 0.01 s).
TEST(Allan, WhiteNoiseMatchesTheClosedFormWithinItsInterval) {
    std::mt19937_64 rng(1);
    std::normal_distribution<double> n(0.0, 2e-3);
    std::vector<double> y(200000);
    for (double& v : y) v = n(rng);
    const auto grid = TauGrid(10000);
    const std::vector<SegmentSums> seg = {SumSegment(y, 0.01, grid)};
    const auto pts = Combine(seg, 0.01, grid);
    ASSERT_GE(pts.size(), 20u);
    int outside = 0;
    for (const AllanPoint& p : pts) {
        const double theory = 2e-3 * std::sqrt(0.01 / p.tau_s);
        outside += theory < p.adev_lo || theory > p.adev_hi;
    }
    // 68 % intervals: about a third outside; the points share data, so allow up to half
    EXPECT_LE(outside, static_cast<int>(pts.size() / 2)) << outside << " of " << pts.size();
    // N (= sigma sqrt(tau0)) fitted within 2 % (the tau = 1 s point alone has edf ~4000: 1.6 %)
    const NoiseTerms t = FitTerms(seg, 0.01, grid, 0.05);
    ASSERT_TRUE(t.ok);
    EXPECT_NEAR(t.arw, 2e-3 * 0.1, 0.02 * 2e-4);
    EXPECT_LT(t.bias, 0.1 * 2e-4);  // no flicker in white noise: B small against N at 1 s
}

// GIVEN othersim's rate noise (white 0.04 deg/s/rtHz, flicker level 0.007 deg/s through an OU
// bank) in seven still segments of five minutes, as a calibration run leaves them
// THEN the fitted B scatters about the configured level (mean of 20 runs within 3 of its standard
// errors: sd of one B ~ 0.0015 from the jackknife, so 3 x 0.0015 / sqrt(20) = 0.001), and the
// window slow noise derived from it matches the OU bank's exact value within 15 % (0.0122 deg/s
// for 60 s windows over 9000 s: sum over components of the window-mean variance minus the
// span-mean's)
TEST(Allan, FlickerFromShortSegmentsIsUnbiasedAndGivesTheSlowNoise) {
    const othersim::NoiseOptions no;
    double sum_b = 0, sum_slow = 0;
    const int runs = 20;
    for (int run = 0; run < runs; ++run) {
        othersim::RateNoise rn(no, 100.0, 500 + run);
        NoiseTracker tr(TrackerConfig::Defaults());
        int64_t seq = 0, t_us = 0;
        for (int s = 0; s < 7; ++s) {
            for (int k = 0; k < 2 * 30000 + 1200 * 100; ++k) {
                const bool moving = k >= 30000;  // 300 s still, 20 min not (a ramp and turns)
                const double v = rn.Next();
                if (!moving || k % 100 == 0) tr.Add({t_us, seq, v, 25.0}, moving);
                ++seq;
                t_us += 10000;
                if (k >= 30000 + 120000) break;
            }
        }
        const NoiseEstimate e = tr.Estimate();
        ASSERT_EQ(e.segments, 7);
        ASSERT_TRUE(e.terms.ok) << e.terms.note;
        sum_b += e.terms.bias;
        sum_slow += SlowNoiseVariance(e.terms.bias, e.terms.rrw, 60, 9000);
    }
    EXPECT_NEAR(sum_b / runs, no.flicker_dps, 0.001);
    double exact = 0;
    const double q = no.flicker_dps / othersim::RateNoise::BankLevelPerUnitSigma();
    auto mean_var = [&](double tc, double w) {
        const double x = w / tc;
        return q * q * 2 * (x - 1 + std::exp(-x)) / (x * x);
    };
    for (double tc : othersim::RateNoise::kOuTauS) exact += mean_var(tc, 60) - mean_var(tc, 9000);
    EXPECT_NEAR(std::sqrt(sum_slow / runs), std::sqrt(exact), 0.15 * std::sqrt(exact));
}

TEST(Allan, WindowIntegralHasItsLimits) {
    // I(a) = integral_a^inf sin^2 u / u^3 du: for large a it is ~ 1/(4 a^2) (sin^2 averages 1/2);
    // for small a it grows like ln(1/a), so halving a adds ln 2.
    EXPECT_NEAR(WindowFlickerIntegral(300.0), 1.0 / (4 * 300.0 * 300.0), 1e-7);
    EXPECT_NEAR(WindowFlickerIntegral(1e-4) - WindowFlickerIntegral(2e-4), std::log(2.0), 1e-6);
    EXPECT_EQ(SlowNoiseVariance(NAN, NAN, 60, 9000), 0.0);
}

TEST(Tracker, RampsMotionAndGapsAreNotNoise) {
    // GIVEN white noise on a unit whose offset follows temperature at 1 mV/K
    std::mt19937_64 rng(3);
    std::normal_distribution<double> n(0.0, 1e-3);
    TrackerConfig cfg;
    NoiseTracker tr(cfg);
    int64_t seq = 0, t_us = 0;
    auto run = [&](double seconds, double temp0, double slope_c_per_s, bool moving, int gap = 0) {
        for (int k = 0; k < static_cast<int>(seconds * 100); ++k) {
            const double temp = temp0 + slope_c_per_s * k * 0.01;
            tr.Add({t_us, seq, 2.5 + 1e-3 * (temp - 25) + n(rng), temp}, moving);
            seq += 1 + (k == 0 ? gap : 0);
            t_us += 10000;
        }
    };
    run(300, 25, 0.0, false);       // quiet: one segment
    run(600, 25, 2.0 / 60, false);  // a 2 degC/min ramp, still: no segment
    run(5, 45, 0, true);            // a turn
    run(200, 45, 0.0005, false);    // settling tail (0.03 degC/min): one segment, detrended
    run(200, 45.1, 0.0, false, 5);  // after 5 lost samples: a new segment
    const NoiseEstimate e = tr.Estimate();
    EXPECT_EQ(e.segments, 3);
    EXPECT_NEAR(e.still_s, 700, 30);  // the slope window trims the segment ends a little
    // THEN the ramps' temperature dependence is not in the Allan deviation: white noise's
    // 1e-3 / sqrt(tau / 0.01 s) within 15 % out to 50 s
    for (const AllanPoint& p : e.adev)
        if (p.tau_s <= 50) {
            EXPECT_NEAR(p.adev, 1e-3 * std::sqrt(0.01 / p.tau_s), 0.15 * p.adev) << p.tau_s;
        }
    tr.Reset();
    EXPECT_EQ(tr.Estimate().segments, 0);
}

// A step of the offset inside one still stretch (a disturbance) must not make the unit look
// noisy: that segment is left out; a segment 30 % noisier (noise that changes with temperature)
// is not.
TEST(Tracker, ASegmentWithAStepIsLeftOutAndOneSomewhatNoisierIsNot) {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> n(0.0, 1e-3);
    NoiseTracker tr(TrackerConfig::Defaults());
    int64_t seq = 0, t_us = 0;
    for (int s = 0; s < 6; ++s) {
        const double scale = s == 2 ? 1.3 : 1.0;
        for (int k = 0; k < 30000; ++k) {
            const double step = (s == 4 && k > 15000) ? 3e-3 : 0.0;
            tr.Add({t_us, seq++, 2.5 + step + scale * n(rng), 25.0}, false);
            t_us += 10000;
        }
        tr.Add({t_us, seq++, 2.5, 25.0}, true);  // a turn between stretches
        t_us += 10000;
    }
    const NoiseEstimate e = tr.Estimate();
    EXPECT_EQ(e.segments, 5);  // the ones used
    EXPECT_NE(e.terms.note.find("1 of 6 still segments left out"), std::string::npos)
        << e.terms.note;
    // white noise of 1e-3 per 10 ms sample: B stays far below the step's ~1e-3 signature
    EXPECT_LT(e.terms.bias, 1e-5);
    for (const AllanPoint& p : e.adev)
        if (p.tau_s >= 1 && p.tau_s <= 30) {
            EXPECT_LT(p.adev, 1.3 * 1e-3 * std::sqrt(0.01 / p.tau_s) * 1.25) << p.tau_s;
        }
}

// The tracker's quiet stretches (windowed temperature slopes, numeric::PrefixLine) and the noise
// terms' weighted fit (the one solver, numeric/least_squares.hpp) give the figures they gave
// before they moved to the shared numerics, on one fixed input (white noise plus a random walk,
// a temperature ramp between quiet stretches, deterministic noise). The reference figures were
// printed by the code as it stood before (its own prefix sums; its own QR solve and normal-
// equation covariance). The stretches are the same arithmetic: equal to the bit. The fit is the
// same method with another order of operations (columns scaled to unit norm first, the
// covariance from the triangular factor): relative 1e-9, far above the round-off of a
// 3-column fit (condition ~1e3: ~1e-13) and far below any change of method (another weighting
// or a dropped term moves the figures by 1e-3 or more).
NoiseEstimate FixedTrackerRun(int stretches) {
    numeric::testing::Lcg u{2024};
    NoiseTracker tr(TrackerConfig::Defaults());
    int64_t seq = 0, t_us = 0;
    double walk = 0.0, temp = 25.0;
    for (int s = 0; s < stretches; ++s) {
        for (int k = 0; k < 210000; ++k) {  // 2100 s still: quiet, then a 2 degC/min ramp
            if (k >= 200000) temp += 2.0 / 60.0 * 0.01;
            walk += 5e-7 * u();
            tr.Add({t_us, seq++, 2.5 + 1e-3 * u() + walk + 1e-3 * (temp - 25.0), temp}, false);
            t_us += 10000;
        }
        tr.Add({t_us, seq++, 2.5, temp}, true);  // a turn between stretches
        t_us += 10000;
    }
    return tr.Estimate();
}

TEST(Tracker, QuietStretchesAndTermsGiveTheFiguresTheyGaveBeforeSharingTheNumerics) {
    struct Expected {
        int stretches, segments;
        double still_s, longest_s;
        double arw, arw_se, bias, bias_se, rrw, rrw_se;
    };
    const Expected cases[] = {
        // four stretches: jackknife errors; the bias term is negative and dropped
        {4, 4, 7912.3999999999996, 1978.0999999999999, 2.8988764480184436e-05,
         1.231498587624416e-07, 0, 0, 1.5381855649657712e-06, 1.1789450713111258e-07},
        // two: the weighted fit's errors (its covariance)
        {2, 2, 3956.1999999999998, 1978.0999999999999, 2.9181088307314935e-05,
         1.233077235814467e-07, 0, NAN, 1.4939928251627099e-06, 6.5301319634388015e-08},
    };
    auto same = [](double got, double want) {
        if (std::isnan(want)) return std::isnan(got);
        return std::fabs(got - want) <= 1e-9 * std::fabs(want);
    };
    for (const Expected& x : cases) {
        SCOPED_TRACE(x.stretches);
        const NoiseEstimate e = FixedTrackerRun(x.stretches);
        EXPECT_EQ(e.segments, x.segments);
        EXPECT_EQ(e.still_s, x.still_s);
        EXPECT_EQ(e.longest_s, x.longest_s);
        ASSERT_TRUE(e.terms.ok);
        EXPECT_PRED2(same, e.terms.arw, x.arw);
        EXPECT_PRED2(same, e.terms.arw_se, x.arw_se);
        EXPECT_PRED2(same, e.terms.bias, x.bias);
        EXPECT_PRED2(same, e.terms.bias_se, x.bias_se);
        EXPECT_PRED2(same, e.terms.rrw, x.rrw);
        EXPECT_PRED2(same, e.terms.rrw_se, x.rrw_se);
        EXPECT_NE(e.terms.note.find("bias instability not resolved"), std::string::npos);
    }
}

// A rest of 6 h without a turn (a long dwell, a slow ramp of a measured run): the tracker holds
// at most 4 max_tau_s of 0.1 s bins (80 000: 1.9 MB) however long the rest, closing a segment every
// 8000 s, and still measures the white noise as one long segment would: N within 2 % (the tau =
// 1 s point alone has edf ~40 000) and the grid's longest tau reached (2000 s).
TEST(Tracker, ALongRestIsHeldToFourLongestTausAndMeasuredAlike) {
    std::mt19937_64 rng(9);
    std::normal_distribution<double> n(0.0, 2e-3);
    const TrackerConfig cfg = TrackerConfig::Defaults();
    NoiseTracker tr(cfg);
    const size_t limit = static_cast<size_t>(4.0 * cfg.max_tau_s / cfg.bin_s);
    size_t most = 0;
    int64_t seq = 0;
    for (int64_t k = 0; k < 6 * 3600 * 100; ++k, ++seq) {
        tr.Add({.utime = k * 10000, .seq = seq, .gyro_v = 2.5 + n(rng), .temp_c = 25.0}, false);
        most = std::max(most, tr.held_bins());
    }
    EXPECT_LT(most, limit);  // the bin that reaches the limit closes the segment
    EXPECT_EQ(most, limit - 1) << "the rest is longer than the limit: it was reached";
    const NoiseEstimate e = tr.Estimate();
    EXPECT_EQ(e.segments, 3);  // 8000 + 8000 + 5600 s
    EXPECT_NEAR(e.still_s, 6 * 3600.0, 1.0);
    ASSERT_TRUE(e.terms.ok) << e.terms.note;
    EXPECT_NEAR(e.terms.arw, 2e-3 * 0.1, 0.02 * 2e-4);
    ASSERT_FALSE(e.adev.empty());
    EXPECT_NEAR(e.adev.back().tau_s, cfg.max_tau_s, 0.5 * cfg.max_tau_s);
}

TEST(Tracker, BadConfigurationIsRefusedNamingTheOption) {
    testing::ExpectRefusedNaming(
        TrackerConfig{}, [](auto& c) { c.quiet_slope_c_per_min = 0; },
        "--noise-quiet-slope-c-per-min");
    const TrackerConfig c = testing::ExpectRefusedNaming(
        TrackerConfig{}, [](auto& o) { o.min_segment_s = 0.01; }, "--noise-min-segment-s");
    EXPECT_THROW(NoiseTracker{c}, std::invalid_argument);
}

}  // namespace
}  // namespace gyrocal::noise
