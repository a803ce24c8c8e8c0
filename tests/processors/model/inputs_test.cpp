// The model inputs with their state (model/inputs.hpp, gyrocal_model.h): dT/dt, branch, time
// since power-on, against what they must be on inputs whose truth is known exactly.
#include "processors/model/inputs.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace gyrocal::model {
namespace {

constexpr int64_t kT0 = 1'000'000'000'000'000;  // [us]

TEST(RateTracker, ASteadyRampIsMeasuredExactlyAtAnySamplePeriod) {
    // GIVEN a noise-free ramp of 3 degC/min sampled at 100 Hz, and the same ramp sampled at
    // irregular intervals (2..37 ms).
    // WHEN tracked for 60 time constants,
    // THEN dT/dt equals the ramp to 1e-9: each average lags by exactly r * its time constant
    // (alpha = dt / (tau + dt)), whatever dt is, and the start-up transient (2 r at first) has
    // decayed as exp(-t / 2 tau) = exp(-30), i.e. to 2e-13 of the ramp; rounding of the averages
    // (~20 degC * 1e-16 / 5 s) is smaller still.
    const double ramp = 3.0 / 60.0;
    for (bool irregular : {false, true}) {
        InputTracker t;
        std::mt19937 rng(3);
        std::uniform_int_distribution<int> step_us(2000, 37000);
        int64_t u = kT0;
        ModelInputs in;
        while (u - kT0 < static_cast<int64_t>(60 * GYROCAL_DEFAULT_RATE_TAU_S * 1e6)) {
            in = t.Update(u, 20.0 + ramp * 1e-6 * static_cast<double>(u - kT0), 5.0);
            u += irregular ? step_us(rng) : 10'000;
        }
        EXPECT_NEAR(in.dtemp_dt_c_per_s, ramp, 1e-9 * ramp) << (irregular ? "irregular" : "100 Hz");
        EXPECT_EQ(in.rate_tau_s, GYROCAL_DEFAULT_RATE_TAU_S);
    }
}

TEST(RateTracker, StartsAtZeroAndWhiteNoiseScattersItAsTheFilterSays) {
    // GIVEN a constant temperature with white noise sigma = 0.05 degC at 100 Hz (dt = 0.01 s).
    // The estimate is (E_tau - E_2tau) / tau; for white input each average has variance
    // sigma^2 dt / (2 tau_i) and their covariance sigma^2 dt / (tau_1 + tau_2) (continuous
    // limit, tau >> dt), so var = sigma^2 dt (1/(2 tau) + 1/(4 tau) - 2/(3 tau)) / tau^2
    //     = sigma^2 dt / (12 tau^3).
    // WHEN tracked for 2e6 samples (2e4 s, ~2000 correlation times of ~2 tau),
    // THEN the first output is 0 and the measured standard deviation matches: its own relative
    // standard error is ~ 1/sqrt(2 * 2000) = 1.6 %; tolerance 4x that, plus 1 % for the
    // continuous-limit approximation (dt / tau = 0.002).
    const double sigma = 0.05, dt = 0.01, tau = GYROCAL_DEFAULT_RATE_TAU_S;
    InputTracker t;
    std::mt19937_64 rng(11);
    std::normal_distribution<double> n(0.0, sigma);
    EXPECT_EQ(t.Update(kT0, 25.0 + n(rng), NAN).dtemp_dt_c_per_s, 0.0);
    double ss = 0.0;
    int count = 0;
    for (int64_t k = 1; k < 2'000'000; ++k) {
        const double r = t.Update(kT0 + k * 10'000, 25.0 + n(rng), NAN).dtemp_dt_c_per_s;
        if (k > 10'000) ss += r * r, ++count;  // past the start-up transient (100 s = 10 tau)
    }
    const double want = sigma * std::sqrt(dt / (12.0 * tau * tau * tau));
    EXPECT_NEAR(std::sqrt(ss / count), want, (4 * 0.016 + 0.01) * want);
}

TEST(BranchTracker, PlayOperatorFollowsTheTravelOfTheTemperature) {
    // GIVEN width 2 degC (half-width 1): start at 20 (branch 0, unknown), rise to 23, fall back
    // to 21.5, rise again to 22.
    // THEN the memory follows at a distance of at most 1 degC: branch = (T - memory) / 1.
    InputTracker t(gyrocal_tracker_config_t{GYROCAL_DEFAULT_RATE_TAU_S, 2.0});
    int64_t u = kT0;
    auto at = [&](double temp_c) {
        u += 10'000;
        return t.Update(u, temp_c, NAN);
    };
    ModelInputs in = at(20.0);
    EXPECT_EQ(in.branch, 0.0);
    EXPECT_EQ(in.heating, 0.0);
    EXPECT_EQ(at(20.5).branch, 0.5);  // within the play: memory stays at 20
    EXPECT_EQ(at(21.0).branch, 1.0);  // reached the edge: heating branch
    in = at(23.0);                    // memory dragged to 22
    EXPECT_EQ(in.branch, 1.0);
    EXPECT_EQ(in.heating, 1.0);
    EXPECT_EQ(at(22.5).branch, 0.5);  // turning: linear transition over the width
    in = at(21.5);
    EXPECT_EQ(in.branch, -0.5);
    EXPECT_EQ(in.heating, 1.0);  // the sign-only form keeps the side last reached
    in = at(21.0);
    EXPECT_EQ(in.branch, -1.0);
    EXPECT_EQ(in.heating, -1.0);
    EXPECT_EQ(at(22.0).branch, 0.0);  // memory now 22: half way back
    EXPECT_EQ(in.branch_width_c, 2.0);
}

TEST(PowerTracker, TimeSincePowerOnFromTheRecordElseFromTheFirstSample) {
    InputTracker given;
    given.PowerOn(kT0 - 30'000'000);
    EXPECT_EQ(given.Update(kT0, 25.0, NAN).time_since_power_s, 30.0);
    EXPECT_FALSE(given.power_on_assumed());
    given.PowerOn(kT0 + 5'000'000);  // a new power cycle
    EXPECT_EQ(given.Update(kT0 + 7'000'000, 25.0, NAN).time_since_power_s, 2.0);

    InputTracker assumed;
    EXPECT_EQ(assumed.Update(kT0, 25.0, NAN).time_since_power_s, 0.0);
    EXPECT_EQ(assumed.Update(kT0 + 1'500'000, 25.0, NAN).time_since_power_s, 1.5);
    EXPECT_TRUE(assumed.power_on_assumed());
}

TEST(Trackers, SamplesOutOfOrderOrWithoutTemperatureLeaveTheStateAlone) {
    InputTracker t;
    t.Update(kT0, 20.0, NAN);
    const ModelInputs a = t.Update(kT0 + 10'000, 20.1, 5.0);
    const ModelInputs late = t.Update(kT0 + 5'000, 30.0, 5.0);  // older than the newest
    EXPECT_EQ(late.dtemp_dt_c_per_s, a.dtemp_dt_c_per_s);
    const ModelInputs nan_t = t.Update(kT0 + 20'000, NAN, 5.0);
    EXPECT_EQ(nan_t.dtemp_dt_c_per_s, a.dtemp_dt_c_per_s);
    EXPECT_EQ(nan_t.supply_v, 5.0);
}

TEST(TrackerConfig, TheTermsOfASetNameOneConfiguration) {
    Model off;
    off.quantity = kOffsetQuantity;
    off.term_names = {"1", "dT", "dTdt(20)", "heating(2.5)"};
    Model sens;
    sens.quantity = kSensitivityQuantity;
    sens.term_names = {"1", "direction"};
    const gyrocal_tracker_config_t c = TrackerConfigFor({&off, &sens});
    EXPECT_EQ(c.rate_tau_s, 20.0);
    EXPECT_EQ(c.branch_width_c, 2.5);
    const gyrocal_tracker_config_t d = TrackerConfigFor(sens);
    EXPECT_EQ(d.rate_tau_s, GYROCAL_DEFAULT_RATE_TAU_S);
    EXPECT_EQ(d.branch_width_c, GYROCAL_SIGN_BRANCH_WIDTH_C);
    sens.term_names = {"1", "heating(1)"};
    EXPECT_THROW(TrackerConfigFor({&off, &sens}), ModelError);  // two branch widths
    sens.term_names = {"1", "dTdt"};
    EXPECT_THROW(TrackerConfigFor({&off, &sens}), ModelError);  // 5 s and 20 s
}

// The lag product shares the rate tracker: it sets the time constant like dTdt, alone or with it,
// and a set whose dTdt and dT*dTdt name two time constants is refused like two dTdt would be.
TEST(TrackerConfig, TheLagProductNamesTheRateTrackersTimeConstant) {
    Model off;
    off.quantity = kOffsetQuantity;
    off.term_names = {"1", "dT", "dTdt(15.2)", "dT*dTdt(15.2)"};
    EXPECT_EQ(TrackerConfigFor(off).rate_tau_s, 15.2);
    off.term_names = {"1", "dT", "dT*dTdt(20)"};
    EXPECT_EQ(TrackerConfigFor(off).rate_tau_s, 20.0);
    off.term_names = {"1", "dT*dTdt"};
    EXPECT_EQ(TrackerConfigFor(off).rate_tau_s, GYROCAL_DEFAULT_RATE_TAU_S);
    off.term_names = {"1", "dTdt(20)", "dT*dTdt(15.2)"};
    EXPECT_THROW(TrackerConfigFor(off), ModelError);
    off.term_names = {"1", "dTdt", "dT*dTdt(5)"};  // the default written out: the same tau
    EXPECT_EQ(TrackerConfigFor(off).rate_tau_s, GYROCAL_DEFAULT_RATE_TAU_S);
    Model sens;
    sens.quantity = kSensitivityQuantity;
    sens.term_names = {"1", "dTdt(20)"};
    off.term_names = {"1", "dT*dTdt(15.2)"};
    EXPECT_THROW(TrackerConfigFor({&off, &sens}), ModelError);  // across the set's two models
}

TEST(SteadyState, DynamicTermsContributeNothing) {
    Model m;
    m.quantity = kOffsetQuantity;
    m.term_names = {"1", "dT", "dTdt(20)", "heating(2.5)", "warmup(300)", "supply"};
    m.coeffs = Eigen::VectorXd::Ones(6);
    m.covariance = Eigen::MatrixXd::Zero(6, 6);
    m.t0_c = 25;
    m.temp_min_c = -40;
    m.temp_max_c = 85;
    EXPECT_EQ(Evaluator(m).Value(SteadyStateInputs(m, 30.0), RangePolicy::kClip), 1.0 + 5.0);
}

}  // namespace
}  // namespace gyrocal::model
