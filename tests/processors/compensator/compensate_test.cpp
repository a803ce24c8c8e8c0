// The live compensator's library: rate and angle against known truth, range policy, atomic swaps
// and refusals of bad sets.
#include "processors/compensator/compensate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/processors/compensator/coeff_set_fixture.hpp"

namespace gyrocal::compensator {
namespace {

// The known set; its run, point count and plateau ids are not read by the compensator.
model::CoeffSet Set(int64_t id) { return testing::KnownCoeffSet(id, ""); }

double Eval(const model::Model& m, double temp_c) {
    model::ModelInputs in;
    in.temp_c = temp_c;
    return model::Evaluator(m).Value(in, model::RangePolicy::kExtrapolate);
}

// gyro_v a unit with exactly the set's curves produces at temp_c and rate_dps.
double GyroV(const model::CoeffSet& s, double temp_c, double rate_dps) {
    return Eval(s.offset, temp_c) + Eval(s.sensitivity, temp_c) * rate_dps;
}

TEST(SensorCompensator, NothingBeforeACoefficientSet) {
    SensorCompensator c;
    EXPECT_EQ(c.Apply({1, 0, 2.5, 25.0}).status, ApplyStatus::kNoCoefficients);
    EXPECT_FALSE(c.has_coefficients());
    EXPECT_EQ(c.coeff_set_id(), -1);
}

TEST(SensorCompensator, RateIsTheTruthAtEveryTemperatureInRange) {
    SensorCompensator c;
    const model::CoeffSet s = Set(10);
    ASSERT_EQ(c.SetCoefficients(s).outcome, SetOutcome::kApplied);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> temp(-10, 60), rate(-300, 300);
    for (int k = 0; k < 1000; ++k) {
        const double t = temp(rng), r = rate(rng);
        const ApplyResult a = c.Apply({1000 + k * 10'000, k, GyroV(s, t, r), t});
        ASSERT_EQ(a.status, ApplyStatus::kOk) << a.detail;
        // 1e-9 deg/s: rounding of a ~2.5 V sum (~4e-16 V) divided by 6 mV/dps is ~1e-13 deg/s.
        EXPECT_NEAR(a.out.rate_dps, r, 1e-9);
        EXPECT_EQ(a.out.range, model::RangeFlag::kInRange);
        EXPECT_EQ(a.out.coeff_set_id, 10);
        EXPECT_GT(a.out.rate_stderr_dps, 0.0);
    }
}

TEST(SensorCompensator, NoisyStillUnitAveragesToZeroRate) {
    // gyro noise sigma_v = 1e-4 V is sigma_v / S = 0.0167 deg/s per sample; the mean of N = 2000
    // samples has sd 0.0167/sqrt(2000) = 3.7e-4 deg/s: |mean| < 4 sd = 1.5e-3 deg/s.
    SensorCompensator c;
    const model::CoeffSet s = Set(10);
    c.SetCoefficients(s);
    std::mt19937_64 rng(2);
    std::normal_distribution<double> noise(0, 1e-4);
    double sum = 0;
    const int kN = 2000;
    for (int k = 0; k < kN; ++k) {
        const double t = 0 + 50.0 * k / kN;  // across the range
        sum += c.Apply({1000 + k * 10'000, k, GyroV(s, t, 0.0) + noise(rng), t}).out.rate_dps;
    }
    EXPECT_NEAR(sum / kN, 0.0, 4 * 1e-4 / 0.006 / std::sqrt(kN));
}

TEST(SensorCompensator, AngleIsTheTrapezoidIntegralOnSampleTime) {
    // rate = A sin(w t): angle = A/w (1 - cos w t). The trapezoid rule's error over a span T with
    // step h is at most T h^2 max|rate''| / 12 = T h^2 A w^2 / 12.
    SensorCompensator c;
    const model::CoeffSet s = Set(10);
    c.SetCoefficients(s);
    const double A = 90.0, w = 2 * M_PI * 0.5;
    const int64_t t0 = 1'000'000'000'000'000;
    double angle = 0;
    const int kN = 400;
    for (int k = 0; k <= kN; ++k) {
        // uneven steps (9..11 ms) to show it integrates on utime, not on sample count
        const int64_t utime = t0 + k * 10'000 + (k % 3 - 1) * 1'000;
        const double ts = 1e-6 * static_cast<double>(utime - t0 + 1'000);  // first sample at t = 0
        angle = c.Apply({utime, k, GyroV(s, 25.0, A * std::sin(w * ts)), 25.0}).out.angle_deg;
        if (k == kN) {
            const double truth = A / w * (1 - std::cos(w * ts));
            const double h = 0.011;
            EXPECT_NEAR(angle, truth, ts * h * h * A * w * w / 12.0);
        }
    }
    EXPECT_NE(angle, 0.0);
}

TEST(SensorCompensator, NewSetSwapsBetweenSamplesAndRestartsTheAngleDuplicateDoesNot) {
    SensorCompensator c;
    model::CoeffSet s = Set(10);
    c.SetCoefficients(s);
    c.Apply({0, 0, GyroV(s, 25, 10.0), 25});
    EXPECT_NEAR(c.Apply({1'000'000, 1, GyroV(s, 25, 10.0), 25}).out.angle_deg, 10.0, 1e-9);
    // the fitter repeats its set on RUN_EVENT stop: not a new calibration
    EXPECT_EQ(c.SetCoefficients(s).outcome, SetOutcome::kDuplicate);
    EXPECT_NEAR(c.Apply({2'000'000, 2, GyroV(s, 25, 10.0), 25}).out.angle_deg, 20.0, 1e-9);
    // a different set: takes effect with the next sample, angle from 0
    model::CoeffSet s2 = Set(11);
    s2.offset.coeffs[0] = 2.4;
    EXPECT_EQ(c.SetCoefficients(s2).outcome, SetOutcome::kApplied);
    const ApplyResult a = c.Apply({3'000'000, 3, GyroV(s2, 25, 5.0), 25});
    EXPECT_EQ(a.out.coeff_set_id, 11);
    EXPECT_NEAR(a.out.rate_dps, 5.0, 1e-9);
    EXPECT_EQ(a.out.angle_deg, 0.0);
    EXPECT_NEAR(c.Apply({4'000'000, 4, GyroV(s2, 25, 5.0), 25}).out.angle_deg, 5.0, 1e-9);
}

TEST(SensorCompensator, BadSetsAreRefusedAndTheOldOneStays) {
    SensorCompensator c;
    const model::CoeffSet good = Set(10);
    c.SetCoefficients(good);
    model::CoeffSet bad = Set(20);
    bad.offset.term_names[2] = "dT^5";
    SetResult r = c.SetCoefficients(bad);
    EXPECT_EQ(r.outcome, SetOutcome::kRejected);
    EXPECT_NE(r.detail.find("unknown term 'dT^5'"), std::string::npos) << r.detail;
    bad = Set(21);
    bad.sensitivity.coeffs =
        Eigen::Vector3d(0.001, 1e-4, 0);  // S(T) = 0.001 + 1e-4 (T-25): 0 at 15 degC
    r = c.SetCoefficients(bad);
    EXPECT_EQ(r.outcome, SetOutcome::kRejected);
    EXPECT_NE(r.detail.find("changes sign"), std::string::npos) << r.detail;
    bad = Set(22);
    bad.sensitivity.coeffs.resize(2);
    EXPECT_EQ(c.SetCoefficients(bad).outcome, SetOutcome::kRejected);
    const ApplyResult a = c.Apply({1, 0, GyroV(good, 30, 1.0), 30});
    EXPECT_EQ(a.out.coeff_set_id, 10);
    EXPECT_NEAR(a.out.rate_dps, 1.0, 1e-9);
}

TEST(SensorCompensator, OutOfRangeIsClippedOrExtrapolatedAndFlagged) {
    const model::CoeffSet s = Set(10);
    CompensatorOptions clip, extrap;
    clip.range_policy = model::RangePolicy::kClip;
    extrap.range_policy = model::RangePolicy::kExtrapolate;
    SensorCompensator cc(clip), ce(extrap);
    cc.SetCoefficients(s);
    ce.SetCoefficients(s);
    const double gyro_v = GyroV(s, 75.0, 20.0);  // a unit that really follows the curves at 75 degC
    const ApplyResult a = cc.Apply({1, 0, gyro_v, 75.0});
    const ApplyResult b = ce.Apply({1, 0, gyro_v, 75.0});
    EXPECT_EQ(a.out.range, model::RangeFlag::kClipped);
    EXPECT_EQ(b.out.range, model::RangeFlag::kExtrapolated);
    EXPECT_NEAR(b.out.rate_dps, 20.0, 1e-9);  // extrapolation is exact for this unit
    // clipped: offset and sensitivity evaluated at 60 degC
    EXPECT_NEAR(a.out.rate_dps, (gyro_v - Eval(s.offset, 60)) / Eval(s.sensitivity, 60), 1e-9);
}

TEST(SensorCompensator, BadSamplesAreRefusedWithTheirReason) {
    SensorCompensator c;
    c.SetCoefficients(Set(10));
    EXPECT_EQ(c.Apply({100, 0, 2.5, 25}).status, ApplyStatus::kOk);
    EXPECT_EQ(c.Apply({100, 1, 2.5, 25}).status, ApplyStatus::kOutOfOrder);
    EXPECT_EQ(c.Apply({50, 2, 2.5, 25}).status, ApplyStatus::kOutOfOrder);
    EXPECT_EQ(c.Apply({200, 3, NAN, 25}).status, ApplyStatus::kNonFinite);
    EXPECT_EQ(c.Apply({300, 4, 2.5, INFINITY}).status, ApplyStatus::kNonFinite);
    EXPECT_EQ(c.Apply({400, 5, 2.5, 25}).status, ApplyStatus::kOk);
}

TEST(SensorCompensator, ExtendedTermsGetTheirInputsFromTheStream) {
    // offset = 2.5 + 1e-3 dT + 3 V/(degC/s) * dT/dt + 4 mV * warmup(60); sensitivity differs by
    // direction (+/-1 %). A noise-free ramp of 1 degC/min, 100 Hz, powered 10 s before the first
    // sample (POWER record).
    model::CoeffSet s = Set(10);
    s.offset.term_names = {"1", "dT", "dTdt", "warmup(60)"};
    s.offset.coeffs = Eigen::Vector4d(2.5, 1e-3, 3.0, 4e-3);
    s.offset.covariance = Eigen::Matrix4d::Zero();
    s.sensitivity.term_names = {"1", "dT", "direction"};
    s.sensitivity.coeffs = Eigen::Vector3d(0.006, 0.0, 6e-5);
    SensorCompensator c;
    ASSERT_EQ(c.SetCoefficients(s).outcome, SetOutcome::kApplied);
    c.PowerOn(-10'000'000);
    const double ramp_c_per_s = 1.0 / 60.0;
    for (int k = 0; k < 30000; ++k) {
        const double ts = 0.01 * k, t = 0.0 + ramp_c_per_s * ts;
        const double rate = (k % 2 ? 50.0 : -50.0);
        const double sens = 0.006 + 6e-5 * (rate > 0 ? 1 : -1);
        const double off =
            2.5 + 1e-3 * (t - 25) + 3.0 * ramp_c_per_s + 4e-3 * std::exp(-(ts + 10.0) / 60.0);
        const ApplyResult a = c.Apply({k * 10'000, k, off + sens * rate, t});
        // Every sample is computed: the inputs are defined from the first sample on.
        ASSERT_EQ(a.status, ApplyStatus::kOk) << k << ": " << a.detail;
        EXPECT_FALSE(c.power_on_assumed());
        EXPECT_DOUBLE_EQ(a.out.inputs.time_since_power_s, ts + 10.0);
        // dT/dt starts at 0 and converges as exp(-t / 2 tau) (tau 5 s): after 200 s the
        // remaining error 3 V/(degC/s) * ramp * exp(-20) is ~1e-10 V, i.e. ~2e-8 deg/s.
        if (ts > 200.0) {
            EXPECT_NEAR(a.out.rate_dps, rate, 1e-6) << k;
        }
    }
}

TEST(SensorCompensator, ANewTrackerConfigurationRestartsThoseTrackersAndSaysSo) {
    SensorCompensator c;
    ASSERT_EQ(c.SetCoefficients(Set(1)).outcome, SetOutcome::kApplied);
    for (int k = 0; k < 100; ++k) c.Apply({k * 10'000, k, 2.5, 20.0 + 0.01 * k});
    model::CoeffSet s = Set(2);
    s.offset.term_names = {"1", "dT", "heating(3)"};
    const SetResult r = c.SetCoefficients(s);
    EXPECT_EQ(r.outcome, SetOutcome::kApplied);
    EXPECT_NE(r.detail.find("trackers restarted"), std::string::npos) << r.detail;
    const ApplyResult a = c.Apply({100 * 10'000, 100, 2.5, 21.0});
    ASSERT_EQ(a.status, ApplyStatus::kOk);
    EXPECT_EQ(a.out.inputs.branch, 0.0);  // unknown again until the temperature travels 1.5 degC
    EXPECT_EQ(a.out.inputs.branch_width_c, 3.0);
    EXPECT_EQ(a.out.inputs.time_since_power_s, 1.0);  // power-on (the first sample) is kept
}

TEST(SensorCompensator, TwoBranchWidthsInOneSetAreRefused) {
    SensorCompensator c;
    model::CoeffSet s = Set(3);
    s.offset.term_names = {"1", "dT", "heating(2)"};
    s.sensitivity.term_names = {"1", "dT", "heating(1)"};
    const SetResult r = c.SetCoefficients(s);
    EXPECT_EQ(r.outcome, SetOutcome::kRejected);
    EXPECT_NE(r.detail.find("branch widths"), std::string::npos) << r.detail;
}

}  // namespace
}  // namespace gyrocal::compensator
