// The ramp fitter: a unit ramped through its range with known offset and sensitivity curves and
// white noise; the fits it publishes during the run and at the stop, against that truth.
#include "processors/fitter/ramp_fitter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "processors/model/convert.hpp"
#include "processors/model/inputs.hpp"
#include "tests/processors/fitter/ramp_truth.hpp"

namespace gyrocal::fitter {
namespace {

constexpr int64_t kS = 1'000'000;
using testing::kRampHz;
using testing::kRampNoiseV;

// The ramp (ramp_truth.hpp) into the fitter, its time told every 10 s of data.
void Feed(RampFitter& f, std::vector<RampFitResult>& during, int64_t* end_utime) {
    testing::FeedRamp(
        [&](const testing::RampSample& g) {
            f.AddGyro("U1", {.utime = g.t_us,
                             .seq = g.seq,
                             .gyro_v = g.gyro_v,
                             .temp_c = g.temp_c,
                             .supply_v = 5.0});
        },
        [&](int64_t t_us, int64_t) {
            f.AddEncoder({t_us, 0, 10000});
        },
        [&](const testing::RampPoint& p) {
            f.AddSensitivity("U1", {p.rotation_id, p.t_us, p.temp_c, p.direction,
                                    p.sensitivity_v_per_dps, testing::kRampSensSeV, true});
        },
        [&](int64_t count, int64_t t_us) {
            if (count % static_cast<int64_t>(10 * kRampHz) == 0)
                for (auto& r : f.OnTime(t_us)) during.push_back(std::move(r));
            *end_utime = t_us;
        });
}

// The fits the tests watch: one per 1800 s of data once 3600 s are in.
RampFitterOptions WatchedOptions() {
    RampFitterOptions o;
    o.refit_interval_s = 1800.0;
    o.min_span_s = 3600.0;
    return o;
}

TEST(RampFitter, FitsTheCurvesOnEveryStillWindowWithinTheirStatedUncertainty) {
    RampFitter f(WatchedOptions());
    f.StartRun("R1");
    std::vector<RampFitResult> during;
    int64_t end = 0;
    Feed(f, during, &end);
    // During the run: the first fit once 3600 s are in, then one per 1800 s of data (140 min:
    // at 60, 90 and 120 min), none final.
    ASSERT_EQ(during.size(), 3u);
    EXPECT_NEAR(static_cast<double>(during[0].report.utime) / kS, 3600.0, 10.0);
    for (const auto& r : during) EXPECT_FALSE(r.report.is_final);
    const auto final_fits = f.Finish(end + kS);
    ASSERT_EQ(final_fits.size(), 1u);
    const RampFitResult& r = final_fits[0];
    ASSERT_TRUE(r.set.has_value()) << r.report.reason;
    EXPECT_TRUE(r.report.is_final);
    EXPECT_EQ(r.report.status, "complete");
    EXPECT_EQ(r.report.coeff_set_id, end + kS) << "a final set is the stop event's";
    EXPECT_EQ(r.set->coeff_set_id, r.report.coeff_set_id);
    EXPECT_EQ(r.set->source, "fitter");
    EXPECT_EQ(r.set->num_rotations, 2 * 28);  // one pair per 300 s of 8400 s
    const model::CoeffSet set = model::FromMsg(*r.set);
    EXPECT_EQ(set.offset.method, "ramp");
    // The truth over the range the fit saw (its bin means: just inside -15..55), the offset's
    // uncertainty below 5 x the noise of one 10 s bin's mean.
    EXPECT_NEAR(set.offset.temp_min_c, -15.0, 0.2);
    EXPECT_NEAR(set.offset.temp_max_c, 55.0, 0.2);
    testing::ExpectTheRampTruth(
        set, {.max_offset_sigma_v = 5.0 * kRampNoiseV / std::sqrt(kRampHz * 10.0)});
    // The run's data are dropped at the stop.
    EXPECT_EQ(f.samples("U1"), 0u);
    EXPECT_TRUE(f.Finish(end + 2 * kS).empty());
}

// The bins held to a limit (max_bins_per_unit; 4096 by default, so a day is fitted on 40 s
// bins): the same 140 min on at most 256 bins merges them twice (40 s), and the final set is
// still the truth within 4 of its own standard uncertainties at every 5 degC, its uncertainty
// about that of the 10 s bins' (the same samples averaged: within 1.5x of the bound above), and
// the analysis says the bins were merged.
TEST(RampFitter, BinsHeldToTheirLimitAreMergedAndStillFitTheTruth) {
    RampFitterOptions o = WatchedOptions();
    o.max_bins_per_unit = 256;
    RampFitter f(o);
    f.StartRun("R1");
    std::vector<RampFitResult> during;
    int64_t end = 0;
    Feed(f, during, &end);
    const auto final_fits = f.Finish(end + kS);
    ASSERT_EQ(final_fits.size(), 1u);
    const RampFitResult& r = final_fits[0];
    ASSERT_TRUE(r.set.has_value()) << r.report.reason;
    ASSERT_TRUE(r.analysis.has_value());
    EXPECT_EQ(r.analysis->bin_s, 40.0);
    EXPECT_LE(r.analysis->n_bins, 256);
    bool noted = false;
    for (const std::string& n : r.analysis->notes) noted |= n.find("bins merged to 40 s") == 0;
    EXPECT_TRUE(noted);
    const model::CoeffSet set = model::FromMsg(*r.set);
    testing::ExpectTheRampTruth(
        set, {.max_offset_sigma_v = 1.5 * 5.0 * kRampNoiseV / std::sqrt(kRampHz * 10.0),
              .sensitivity = false});
    o.max_bins_per_unit = 10;
    EXPECT_NE(o.Validate().find("max bins per unit"), std::string::npos);
}

// The same triangle with what the rig's day-long runs have and Feed lacks: slow noise (an
// Ornstein-Uhlenbeck offset of 0.1 mV, 120 s correlation time: as large as a 10 s bin's white
// scatter) and a turn out and back every 300 s (so the still stretches are 7 bins of 40 s). No
// effect is in the data: the truth is "adequate". (Noise much slower than the still stretches,
// say 600 s, cannot be measured from them at any bin length: the analysis then flags the
// temperature bands it moves, at 10 s as at 40 s; processors/analysis/README.md.)
void FeedWithTurnsAndSlowNoise(RampFitter& f, int64_t* end_utime) {
    std::mt19937_64 rng(11);
    std::normal_distribution<double> n(0.0, 1.0);
    const double rate = 1.0 / 60.0, dt_s = 1.0 / kRampHz, ou_tau_s = 120.0, ou_sd_v = 1e-4;
    const double phi = std::exp(-dt_s / ou_tau_s);
    const double legs[] = {40.0 / rate, 70.0 / rate, 30.0 / rate};
    constexpr int32_t kCountsPerRev = 36000;
    double t_c = 25.0, t_s = 0.0, ou_v = 0.0;
    int64_t seq = 0;
    for (int leg = 0; leg < 3; ++leg) {
        const double dir = leg == 1 ? 1.0 : -1.0;
        for (double s = 0; s < legs[leg]; s += dt_s, t_s += dt_s) {
            t_c += dir * rate * dt_s;
            ou_v = phi * ou_v + ou_sd_v * std::sqrt(1.0 - phi * phi) * n(rng);
            // 0-2 s into each 300 s: +45 deg/s, 2-4 s: -45 deg/s (90 deg out and back).
            const double in_cycle_s = std::fmod(t_s, 300.0);
            const double rate_dps = in_cycle_s < 2.0 ? 45.0 : in_cycle_s < 4.0 ? -45.0 : 0.0;
            const double angle_deg = in_cycle_s < 2.0   ? 45.0 * in_cycle_s
                                     : in_cycle_s < 4.0 ? 90.0 - 45.0 * (in_cycle_s - 2.0)
                                                        : 0.0;
            const int64_t u = static_cast<int64_t>(std::llround(t_s * 1e6));
            f.AddGyro("U1", {.utime = u,
                             .seq = seq++,
                             .gyro_v = testing::RampOffsetTrue(t_c) +
                                       testing::RampSensTrue(t_c) * rate_dps + ou_v +
                                       kRampNoiseV * n(rng),
                             .temp_c = t_c,
                             .supply_v = 5.0});
            f.AddEncoder({u, std::llround(angle_deg * kCountsPerRev / 360.0), kCountsPerRev});
            if (seq % static_cast<int64_t>(10 * kRampHz) == 0) f.OnTime(u);
            *end_utime = u;
        }
    }
}

// Bins merged by the limit are judged as the 10 s bins are: the noise the analysis measures
// (and draws its nulls from) does not depend on the bin length, so the final set of a run held
// to 256 bins (40 s) gets the verdict the unlimited run gets, and both the truth's: adequate.
TEST(RampFitter, BinsHeldToTheirLimitGetTheVerdictOfTheTenSecondBins) {
    std::vector<RampFitResult> finals;
    for (int64_t limit : {0, 256}) {
        RampFitterOptions o = WatchedOptions();
        o.max_bins_per_unit = limit;
        RampFitter f(o);
        f.StartRun("R1");
        int64_t end = 0;
        FeedWithTurnsAndSlowNoise(f, &end);
        auto out = f.Finish(end + kS);
        ASSERT_EQ(out.size(), 1u);
        ASSERT_TRUE(out[0].analysis.has_value());
        finals.push_back(std::move(out[0]));
    }
    EXPECT_EQ(finals[0].analysis->bin_s, 10.0);
    EXPECT_EQ(finals[1].analysis->bin_s, 40.0);
    for (const RampFitResult& r : finals)
        EXPECT_EQ(r.analysis->outcome, analysis::Outcome::kAdequate)
            << r.analysis->bin_s << " s bins: " << r.analysis->headline;
}

TEST(RampFitter, NoRunNoFitAndAUnitWithTooLittleDataSaysWhy) {
    RampFitter f(RampFitterOptions::Defaults());
    f.AddGyro("U1", {.utime = 0, .seq = 0, .gyro_v = 2.5, .temp_c = 25.0, .supply_v = 5.0});
    EXPECT_TRUE(f.OnTime(10000 * kS).empty()) << "outside a run";
    f.StartRun("R1");
    const auto out = f.Finish(kS);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_FALSE(out[0].set.has_value());
    EXPECT_EQ(out[0].report.status, "none");
    EXPECT_FALSE(out[0].report.reason.empty());
}

TEST(RampFitter, BadOptionsNameTheOption) {
    RampFitterOptions o;
    o.refit_interval_s = 1.0;
    EXPECT_NE(o.Validate().find("refit interval"), std::string::npos);
    EXPECT_THROW(RampFitter{o}, std::invalid_argument);
    o = RampFitterOptions::Defaults();
    o.min_span_s = -1.0;
    EXPECT_NE(o.Validate().find("min span"), std::string::npos);
    o = RampFitterOptions::Defaults();
    o.analysis.bins.bin_s = 0.0;
    EXPECT_NE(o.Validate().find("analysis: bin_s"), std::string::npos);
}

}  // namespace
}  // namespace gyrocal::fitter
