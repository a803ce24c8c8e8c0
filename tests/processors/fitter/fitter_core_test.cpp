// The fitter's state machine without the bus: run scoping, when a set is emitted, what it holds,
// and which inputs are refused with which reason.
#include "processors/fitter/fitter_core.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>

#include "processors/model/convert.hpp"
#include "processors/noise/allan.hpp"
#include "tests/processors/fitter/fitter_fixture.hpp"

namespace gyrocal::fitter {
namespace {

using testing::OffsetTruthV;

run_event_t Event(const std::string& what, const std::string& run,
                  std::vector<std::string> sensors = {"S01"}) {
    return testing::FitterRunEvent(run, what, 0, sensors);
}

// The offset truth's 60 s plateau starting at `id` [us].
plateau_t Plateau(double temp_c, int64_t id, const std::string& run = "A",
                  const std::string& sensor = "S01") {
    return testing::TruthPlateau(run, sensor, temp_c, id);
}

// A 5 s turn starting at `id` [us] that measures a sensitivity linear in temperature.
sensitivity_point_t Rotation(double temp_c, int64_t id, int dir, bool accepted = true) {
    sensitivity_point_t r = testing::WindowOf<sensitivity_point_t>("S01", "A", id, id + 5'000'000);
    r.direction = static_cast<int8_t>(dir);
    r.temp_c = temp_c;
    r.sensitivity_v_per_dps = 0.006 + 1e-6 * temp_c;
    r.sensitivity_stderr_v_per_dps = 2e-6;
    r.accepted = accepted;
    return r;
}

bool HasRejection(const CoreOutput& out, const std::string& key) {
    for (const Rejection& r : out.rejections)
        if (r.key == key) return true;
    return false;
}

TEST(FitterCore, EmitsWhenAFitBecomesPossibleAndAgainOnStop) {
    FitterCore core(CoreOptions::Defaults());
    EXPECT_TRUE(core.OnRunEvent(Event("start", "A")).publish.empty());
    CoreOutput out = core.OnPlateau(Plateau(-10, 100), "S01");
    EXPECT_TRUE(out.publish.empty());
    EXPECT_TRUE(out.rejections.empty());  // too few temperatures is expected mid-run, not a refusal
    out = core.OnPlateau(Plateau(30, 200), "S01");
    EXPECT_TRUE(out.publish.empty());
    EXPECT_NE(core.Summaries()["S01"].text.find("too_few_temperatures"), std::string::npos);
    out = core.OnPlateau(Plateau(60, 300), "S01");
    ASSERT_EQ(out.publish.size(), 1u);
    const model::CoeffSet set = model::FromMsg(out.publish[0]);
    EXPECT_EQ(set.offset.method, "3point");
    EXPECT_EQ(set.sensitivity.method, "nominal");
    EXPECT_EQ(set.plateau_ids, (std::vector<int64_t>{100, 200, 300}));
    EXPECT_TRUE(set.rotation_ids.empty());
    EXPECT_EQ(set.coeff_set_id, 300 + 60'000'000);  // utime of the newest plateau
    EXPECT_EQ(set.run_id, "A");
    EXPECT_EQ(set.source, "fitter");
    EXPECT_NE(core.Summaries()["S01"].text.find("NOMINAL"), std::string::npos);

    // An unaccepted rotation changes nothing: no new set.
    out = core.OnSensitivity(Rotation(60, 400, 1, false), "S01");
    EXPECT_TRUE(out.publish.empty());
    EXPECT_EQ(core.not_accepted_rotations(), 1);
    // Stop: the same models once more, as the FINAL set: its id is the stop event's (the input
    // that made it final), and its report says it is partial (nominal sensitivity) and why.
    run_event_t stop = Event("stop", "A");
    stop.utime = 500 + 90'000'000;
    out = core.OnRunEvent(stop);
    ASSERT_EQ(out.publish.size(), 1u);
    EXPECT_EQ(out.publish[0].coeff_set_id, stop.utime);
    EXPECT_EQ(model::FromMsg(out.publish[0]).offset.coeffs, set.offset.coeffs);
    ASSERT_EQ(out.reports.size(), 1u);
    const fit_report_t& r = out.reports[0];
    EXPECT_TRUE(r.is_final);
    EXPECT_EQ(r.coeff_set_id, stop.utime);
    EXPECT_EQ(r.status, "partial");
    EXPECT_NE(r.reason.find("no accepted rotation"), std::string::npos) << r.reason;
    EXPECT_NE(r.offset_detail.find("cannot check"), std::string::npos) << r.offset_detail;
    EXPECT_NE(r.slow_noise_source.find("none"), std::string::npos) << r.slow_noise_source;
    EXPECT_TRUE(HasRejection(out, "fit_partial"));
}

// On several hosts the run's stop can overtake the last rotation's result: a point of the run
// after its stop remakes the final set with it, 1 us after the previous final one, so that the
// newest set of the unit is final and uses every point.
TEST(FitterCore, APointAfterTheStopRemakesTheFinalSetWithIt) {
    FitterCore core(CoreOptions::Defaults());
    core.OnRunEvent(Event("start", "A"));
    for (int k = 0; k < 3; ++k) {
        core.OnPlateau(Plateau(-10 + 35 * k, 100 * (k + 1)), "S01");
        core.OnSensitivity(Rotation(-10 + 35 * k, 100 * (k + 1) + 10, 1), "S01");
    }
    core.OnSensitivity(Rotation(-10, 120, -1), "S01");
    core.OnSensitivity(Rotation(25, 220, -1), "S01");
    run_event_t stop = Event("stop", "A");
    stop.utime = 900'000'000;
    CoreOutput out = core.OnRunEvent(stop);
    ASSERT_EQ(out.publish.size(), 1u);
    EXPECT_EQ(out.publish[0].coeff_set_id, stop.utime);
    EXPECT_EQ(out.publish[0].num_rotations, 5);
    // WHEN the last rotation's result arrives after the stop
    out = core.OnSensitivity(Rotation(60, 320, -1), "S01");
    // THEN a final set with it, its id the next microsecond, and a final report of that set
    ASSERT_EQ(out.publish.size(), 1u);
    EXPECT_EQ(out.publish[0].coeff_set_id, stop.utime + 1);
    EXPECT_EQ(out.publish[0].num_rotations, 6);
    ASSERT_EQ(out.reports.size(), 1u);
    EXPECT_TRUE(out.reports[0].is_final);
    EXPECT_EQ(out.reports[0].coeff_set_id, stop.utime + 1);
    // AND a new run's points are fitted as mid-run points again
    core.OnRunEvent(Event("start", "B"));
    plateau_t p = Plateau(-10, 1000, "B");
    out = core.OnPlateau(p, "S01");
    EXPECT_TRUE(out.reports.empty());
}

TEST(FitterCore, RotationsBecomeTheSensitivityModel) {
    FitterCore core(CoreOptions::Defaults());
    core.OnRunEvent(Event("start", "A"));
    for (auto [t, id] : {std::pair{-10.0, 100}, {30.0, 200}, {60.0, 300}})
        core.OnPlateau(Plateau(t, id), "S01");
    // Rotations at only two temperatures: a weighted mean, said so in the summary.
    core.OnSensitivity(Rotation(-10, 110, +1), "S01");
    CoreOutput out = core.OnSensitivity(Rotation(-10, 120, -1), "S01");
    ASSERT_EQ(out.publish.size(), 1u);
    EXPECT_EQ(model::FromMsg(out.publish[0]).sensitivity.method, "mean");
    EXPECT_NE(core.Summaries()["S01"].text.find("sensitivity mean"), std::string::npos);
    EXPECT_NE(core.Summaries()["S01"].text.find("PARTIAL"), std::string::npos);
    ASSERT_EQ(out.reports.size(), 1u);
    EXPECT_EQ(out.reports[0].status, "partial");
    EXPECT_FALSE(out.reports[0].is_final);
    core.OnSensitivity(Rotation(30, 210, +1), "S01");
    core.OnSensitivity(Rotation(30, 220, -1), "S01");
    core.OnSensitivity(Rotation(60, 310, +1), "S01");
    out = core.OnSensitivity(Rotation(60, 320, -1), "S01");
    ASSERT_EQ(out.publish.size(), 1u);
    const model::CoeffSet set = model::FromMsg(out.publish[0]);
    EXPECT_EQ(set.sensitivity.method, "wls");  // 6 points: wls, degree chosen by AIC
    EXPECT_EQ(set.rotation_ids, (std::vector<int64_t>{110, 120, 210, 220, 310, 320}));
    // the newest input: the 60 degC plateau's end (300 + 60 s) is later than any rotation's end
    // here
    EXPECT_EQ(set.coeff_set_id, std::max<int64_t>(300 + 60'000'000, 320 + 5'000'000));
    // The sensitivity truth is linear: the fit reproduces it at the points within 4 sigma of
    // the points' 2e-6 standard error (the fit's own error is smaller than a single point's).
    const model::Evaluator sens(set.sensitivity);
    model::ModelInputs in;
    in.temp_c = 30;
    EXPECT_NEAR(sens.Value(in, model::RangePolicy::kClip), 0.006 + 30e-6, 8e-6);
}

TEST(FitterCore, RunStartClearsAndOtherRunsAreRefused) {
    FitterCore core(CoreOptions::Defaults());
    core.OnRunEvent(Event("start", "A"));
    core.OnPlateau(Plateau(-10, 100), "S01");
    core.OnRunEvent(Event("start", "A"));  // a repeated start of the same run keeps the points
    EXPECT_EQ(core.Summaries().size(), 1u);
    core.OnRunEvent(Event("start", "B"));
    EXPECT_TRUE(core.Summaries().empty());
    const CoreOutput out = core.OnPlateau(Plateau(30, 200, "A"), "S01");
    EXPECT_TRUE(HasRejection(out, "wrong_run"));
    EXPECT_TRUE(core.Summaries().empty());
}

TEST(FitterCore, BadInputIsRefusedWithItsReason) {
    FitterCore core(CoreOptions::Defaults());
    core.OnRunEvent(Event("start", "A", {"S01", "S02"}));
    EXPECT_TRUE(HasRejection(core.OnPlateau(Plateau(30, 1, "A", "S02"), "S01"), "wrong_sensor"));
    EXPECT_TRUE(HasRejection(core.OnPlateau(Plateau(30, 2, "A", "S07"), "S07"), "unknown_sensor"));
    plateau_t p = Plateau(30, 3);
    p.temp_mean_c = NAN;
    EXPECT_TRUE(HasRejection(core.OnPlateau(p, "S01"), "non_finite"));
    p = Plateau(30, 4);
    p.gyro_sem_v = 0;
    EXPECT_TRUE(HasRejection(core.OnPlateau(p, "S01"), "bad_sem"));
    sensitivity_point_t r = Rotation(30, 5, 1);
    r.sensitivity_v_per_dps = INFINITY;
    EXPECT_TRUE(HasRejection(core.OnSensitivity(r, "S01"), "non_finite"));
    EXPECT_TRUE(core.Summaries().empty());  // nothing was kept
}

// Temperatures closer than the separation are data, not a refusal: they add no degree, so the
// set stays incomplete mid-run (nothing published), and the run's stop publishes what they allow
// (a line through two separated temperatures), marked partial with the reason.
TEST(FitterCore, CloseTemperaturesAreDataAndTheStopPublishesWhatTheyAllow) {
    FitterCore core(CoreOptions::Defaults());
    core.OnRunEvent(Event("start", "A"));
    core.OnPlateau(Plateau(20, 100), "S01");
    core.OnPlateau(Plateau(23, 200), "S01");
    CoreOutput out = core.OnPlateau(Plateau(60, 300), "S01");
    EXPECT_TRUE(out.publish.empty());
    EXPECT_TRUE(out.rejections.empty());  // too few separated temperatures: normal mid-run
    EXPECT_NE(core.Summaries()["S01"].text.find("too_few_temperatures"), std::string::npos);
    // a replay of the same plateau is counted as such
    out = core.OnPlateau(Plateau(60, 300), "S01");
    EXPECT_EQ(core.duplicates(), 1);
    out = core.OnRunEvent(Event("stop", "A"));
    ASSERT_EQ(out.publish.size(), 1u);
    const model::CoeffSet set = model::FromMsg(out.publish[0]);
    EXPECT_EQ(set.offset.term_names, (std::vector<std::string>{"1", "dT"}));
    EXPECT_EQ(set.plateau_ids, (std::vector<int64_t>{100, 200, 300}));
    EXPECT_EQ(set.offset.temp_min_c, 20);
    EXPECT_EQ(set.offset.temp_max_c, 60);
    ASSERT_EQ(out.reports.size(), 1u);
    EXPECT_EQ(out.reports[0].status, "partial");
    EXPECT_NE(out.reports[0].reason.find("too_few_temperatures"), std::string::npos)
        << out.reports[0].reason;
    EXPECT_TRUE(HasRejection(out, "fit_partial"));
}

TEST(FitterCore, OnePlateauAtStopGivesAConstantOffsetAndNoPlateauGivesAReportOfNone) {
    FitterCore core(CoreOptions::Defaults());
    core.OnRunEvent(Event("start", "A", {"S01", "S02"}));
    core.OnPlateau(Plateau(20, 100), "S01");
    sensitivity_point_t r = Rotation(20, 110, 1);
    r.sensor_id = "S02";
    core.OnSensitivity(r, "S02");
    const CoreOutput out = core.OnRunEvent(Event("stop", "A", {"S01", "S02"}));
    ASSERT_EQ(out.publish.size(), 1u);
    EXPECT_EQ(out.publish[0].sensor_id, "S01");
    EXPECT_EQ(out.publish[0].offset.method, "mean");
    ASSERT_EQ(out.reports.size(), 2u);
    for (const fit_report_t& rep : out.reports) {
        if (rep.sensor_id == "S01") {
            EXPECT_EQ(rep.status, "partial");
        } else {
            EXPECT_EQ(rep.status, "none");
            EXPECT_EQ(rep.coeff_set_id, -1);
            EXPECT_NE(rep.reason.find("no plateau"), std::string::npos) << rep.reason;
        }
    }
    EXPECT_TRUE(HasRejection(out, "fit_refused"));
}

// Plateau means carry slow noise their window's standard error cannot show (the gyro's bias
// instability keeps its value through the window). Seed method, three plateaus: without the
// option the 3-point covariance (no dof to estimate any overdispersion) claims errors 5x too
// small; with it the claimed standard error is the scatter's.
TEST(FitterCore, PlateauSlowNoiseMakesTheThreePointUncertaintyHonest) {
    const double sem_v = 2e-5, slow_dps = 0.015, s_v_per_dps = 0.006;
    const double slow_v = slow_dps * s_v_per_dps;  // 9e-5 V: 4.5x the window's standard error
    const int trials = 2000;
    std::mt19937_64 rng(42);
    std::normal_distribution<double> n01;
    double z2_with = 0.0, z2_without = 0.0;
    for (int k = 0; k < trials; ++k) {
        CoreOptions with = CoreOptions::Defaults();
        with.plateau_slow_noise_dps = slow_dps;
        FitterCore a(with), b(CoreOptions::Defaults());
        a.OnRunEvent(Event("start", "A"));
        b.OnRunEvent(Event("start", "A"));
        CoreOutput out_a, out_b;
        int64_t id = 100;
        for (double t : {-10.0, 30.0, 60.0}) {
            plateau_t p = Plateau(t, id += 100);
            p.gyro_mean_v += sem_v * n01(rng) + slow_v * n01(rng);
            out_a = a.OnPlateau(p, "S01");
            out_b = b.OnPlateau(p, "S01");
        }
        ASSERT_EQ(out_a.publish.size(), 1u);
        ASSERT_EQ(out_b.publish.size(), 1u);
        // At 45 degC, between plateaus: the error of the fit over its own claimed uncertainty.
        model::ModelInputs in;
        in.temp_c = 45.0;
        for (auto [out, z2] : {std::pair{&out_a, &z2_with}, std::pair{&out_b, &z2_without}}) {
            const model::CoeffSet set = model::FromMsg(out->publish[0]);
            const model::Evaluation e =
                model::Evaluator(set.offset).Evaluate(in, model::RangePolicy::kClip);
            *z2 += (e.value - OffsetTruthV(45.0)) * (e.value - OffsetTruthV(45.0)) / e.variance;
        }
    }
    // Mean z^2 is 1 when the claimed variance is the true one; its estimate from 2000 trials has
    // sd sqrt(2/2000) = 0.032: 4 sigma = 0.13. Without the option it is (1 + 4.5^2) = 21.
    std::printf(
        "[ fitter ] 3-point fits, slow noise 4.5x the window SEM: mean z^2 at 45 degC %.3f "
        "with --plateau-slow-noise-dps, %.1f without\n",
        z2_with / trials, z2_without / trials);
    EXPECT_NEAR(z2_with / trials, 1.0, 0.13);
    EXPECT_GT(z2_without / trials, 10.0);
}

TEST(FitterCore, OptionsAreValidated) {
    CoreOptions o;
    EXPECT_EQ(o.Validate(), "");
    o.nominal_sensitivity_v_per_dps = 0;
    EXPECT_NE(o.Validate().find("--nominal-sensitivity-v-per-dps"), std::string::npos);
    o = CoreOptions{};
    o.fit.max_degree = 4;
    EXPECT_NE(o.Validate().find("--max-degree"), std::string::npos);
    o = CoreOptions{};
    o.plateau_slow_noise_dps = -1;  // from the run's Allan deviation: valid
    EXPECT_EQ(o.Validate(), "");
    o.plateau_slow_noise_dps = 11;
    EXPECT_NE(o.Validate().find("--plateau-slow-noise-dps"), std::string::npos);
    o.plateau_slow_noise_dps = NAN;
    EXPECT_NE(o.Validate().find("--plateau-slow-noise-dps"), std::string::npos);
    o = CoreOptions{};
    o.outliers.family_alpha = 0.7;
    EXPECT_NE(o.Validate().find("--outlier-alpha"), std::string::npos);
    o = CoreOptions{};
    o.pool_alpha = 0;
    EXPECT_NE(o.Validate().find("--pool-alpha"), std::string::npos);
    o = CoreOptions{};
    o.repeat_tolerance_c = -1;
    EXPECT_NE(o.Validate().find("--repeat-tolerance-c"), std::string::npos);
}

// A unit's five plateaus leave its cubic reference one dof; the fitter pools the other units'
// reference chi2 and dof (fitter_core.hpp), so each unit's c is the run's.
TEST(FitterCore, OverdispersionIsPooledAcrossTheRunsUnits) {
    // GIVEN two units whose plateaus scatter by a fixed pattern of +-3 stated errors
    FitterCore core(CoreOptions::Defaults());
    core.OnRunEvent(Event("start", "A", {"S01", "S02"}));
    const std::vector<double> temps = {-40, -10, 25, 55, 85};
    const std::vector<std::vector<double>> pattern = {{3, -3, 3, -3, 3}, {-3, 3, 3, -3, 0}};
    std::vector<std::vector<fit::FitPoint>> own(2);
    for (size_t u = 0; u < 2; ++u) {
        const std::string sensor = u == 0 ? "S01" : "S02";
        for (size_t i = 0; i < temps.size(); ++i) {
            plateau_t p = Plateau(temps[i], static_cast<int64_t>(1000 * i + u), "A", sensor);
            p.gyro_mean_v += pattern[u][i] * p.gyro_sem_v;
            core.OnPlateau(p, sensor);
            fit::FitPoint pt;
            pt.inputs.temp_c = p.temp_mean_c;
            pt.y = p.gyro_mean_v;
            pt.sigma_y = p.gyro_sem_v;
            pt.id = p.plateau_id;
            own[u].push_back(pt);
        }
    }
    // WHEN the run stops (every unit refitted with the others' latest evidence)
    const CoreOutput out = core.OnRunEvent(Event("stop", "A", {"S01", "S02"}));
    ASSERT_EQ(out.publish.size(), 2u);
    // THEN each unit's c is the pooled (chi2_1 + chi2_2) / (1 + 1) of the units' own references
    const fit::FitResult a = fit::FitPolynomial(own[0], "offset_v");
    const fit::FitResult b = fit::FitPolynomial(own[1], "offset_v");
    ASSERT_EQ(a.reference_dof, 1);
    ASSERT_EQ(b.reference_dof, 1);
    const double pooled = (a.reference_chi2 + b.reference_chi2) / 2.0;
    for (const auto& [id, summary] : core.Summaries()) {
        EXPECT_NEAR(summary.offset_overdispersion, pooled, 1e-9 * pooled) << id;
        EXPECT_NE(summary.text.find("on 2 dof"), std::string::npos) << summary.text;
    }
    // AND the published covariance is the fit's with that c (Birge ratio, c > 1 here)
    ASSERT_GT(pooled, 1.0);
    fit::FitOptions o;
    o.pooled_chi2 = b.reference_chi2;
    o.pooled_dof = 1;
    const fit::FitResult a_pooled = fit::FitPolynomial(own[0], "offset_v", o);
    const model::CoeffSet s01 =
        model::FromMsg(out.publish[0].sensor_id == "S01" ? out.publish[0] : out.publish[1]);
    EXPECT_TRUE(s01.offset.covariance.isApprox(a_pooled.model.covariance, 1e-12));
    EXPECT_DOUBLE_EQ(a_pooled.covariance_scale, pooled);
}

}  // namespace
}  // namespace gyrocal::fitter

namespace gyrocal::fitter {
namespace {

noise_t Noise(double bias_v, double bias_se_v, int64_t utime, const std::string& sensor = "S01") {
    noise_t n = testing::Stamped<noise_t>(utime, sensor, "A");
    n.still_s = 1800;
    n.n_segments = 6;
    n.bias_instability_v = bias_v;
    n.bias_instability_stderr_v = bias_se_v;
    n.rrw_v_rts = 0.0;
    n.arw_v_rthz = 3e-4;
    return n;
}

// Without a hand-given value the slow noise is the unit's own Allan estimate: the newest NOISE
// not later than its newest plateau, B and K through noise::SlowNoiseVariance for the plateaus'
// window and span, widened by nu/(nu - 2) for the estimate's scatter; a later NOISE waits for
// the next plateau.
TEST(FitterCore, SlowNoiseComesFromTheUnitsAllanEstimate) {
    FitterCore core(CoreOptions::Defaults());
    core.OnRunEvent(Event("start", "A"));
    const int64_t t0 = 1'000'000'000;
    core.OnNoise(Noise(5e-5, 1e-5, t0 - 1), "S01");
    core.OnPlateau(Plateau(-10, t0), "S01");
    core.OnPlateau(Plateau(30, t0 + 3600'000'000), "S01");
    core.OnNoise(Noise(9e-5, 1e-5, t0 + 7200'000'000 + 60'000'000 - 1), "S01");   // before the 3rd
    core.OnNoise(Noise(5e-4, 1e-5, t0 + 7200'000'000 + 60'000'000 + 10), "S01");  // after it
    const CoreOutput out = core.OnPlateau(Plateau(60, t0 + 7200'000'000), "S01");
    ASSERT_EQ(out.reports.size(), 1u);
    const fit_report_t& r = out.reports[0];
    const double span_s = 7200 + 60, nu = 9e-5 * 9e-5 / (2 * 1e-5 * 1e-5);
    const double want = std::sqrt(noise::SlowNoiseVariance(9e-5, 0.0, 60, span_s) * nu / (nu - 2));
    EXPECT_NEAR(r.slow_noise_v, want, 1e-12);
    EXPECT_NE(r.slow_noise_source.find("Allan deviation of this run (NOISE_S01"), std::string::npos)
        << r.slow_noise_source;
    EXPECT_NEAR(r.slow_noise_dps, want / 0.006, 1e-9);  // nominal sensitivity: no rotations
    // the plateaus' errors in the set: the 3-point covariance at a plateau is its error squared
    const model::CoeffSet set = model::FromMsg(out.publish.at(0));
    model::ModelInputs in;
    in.temp_c = 30;
    EXPECT_NEAR(std::sqrt(model::Evaluate(set.offset, in, model::RangePolicy::kClip).variance),
                std::hypot(2e-5, want), 1e-12);
    // a hand-given value wins, and says so
    CoreOptions given = CoreOptions::Defaults();
    given.plateau_slow_noise_dps = 0.01;
    FitterCore g(given);
    g.OnRunEvent(Event("start", "A"));
    g.OnNoise(Noise(9e-5, 1e-5, t0 - 1), "S01");
    for (double t : {-10.0, 30.0})
        g.OnPlateau(Plateau(t, t0 + static_cast<int64_t>(t * 1e8)), "S01");
    const CoreOutput go = g.OnPlateau(Plateau(60, t0 + 7200'000'000), "S01");
    ASSERT_EQ(go.reports.size(), 1u);
    EXPECT_NEAR(go.reports[0].slow_noise_v, 0.01 * 0.006, 1e-15);
    EXPECT_NE(go.reports[0].slow_noise_source.find("given"), std::string::npos);
}

// One unit's plateau 30 sigma off is left out (named in its report); a unit whose scatter is far
// beyond the others' everywhere is fitted on its own evidence and left out of the others' pool;
// the clean units' covariance is what they would have without the bad unit (no contamination).
TEST(FitterCore, ABadUnitDoesNotContaminateTheOthers) {
    const std::vector<double> temps = {25, -40, -10, 45, 65, 85};
    std::mt19937_64 rng(21);
    std::normal_distribution<double> n01;
    std::map<std::string, std::vector<double>> z;  // the same noise for a unit in both runs
    for (const std::string id : {"S01", "S02", "S03", "S04"})
        for (size_t i = 0; i < temps.size(); ++i) z[id].push_back(n01(rng));
    auto run = [&](bool with_bad) {
        FitterCore core(CoreOptions::Defaults());
        std::vector<std::string> ids = {"S01", "S02", "S03"};
        if (with_bad) ids.push_back("S04");
        core.OnRunEvent(Event("start", "A", ids));
        for (size_t i = 0; i < temps.size(); ++i)
            for (const std::string& id : ids) {
                plateau_t p =
                    Plateau(temps[i], static_cast<int64_t>(1000 * i + (id.back() - '0')), "A", id);
                // S04: +-40 stated errors at every plateau, a scatter no curve absorbs
                p.gyro_mean_v += id == "S04" ? 40 * 2e-5 * (i % 2 ? -1.0 : 1.0) : 2e-5 * z[id][i];
                if (id == "S02" && i == 3) p.gyro_mean_v += 30 * 2e-5;  // S02: one outlier
                core.OnPlateau(p, id);
            }
        return core.OnRunEvent(Event("stop", "A", ids));
    };
    const CoreOutput clean = run(false), dirty = run(true);
    std::map<std::string, const fit_report_t*> rep;
    for (const auto& r : dirty.reports) rep[r.sensor_id] = &r;
    ASSERT_EQ(rep.size(), 4u);
    ASSERT_EQ(rep["S02"]->num_excluded, 1) << rep["S02"]->offset_detail;
    EXPECT_EQ(rep["S02"]->excluded[0].kind, "plateau");
    EXPECT_EQ(rep["S02"]->excluded[0].item_id, 3002);
    EXPECT_NE(rep["S04"]->offset_detail.find("disagrees"), std::string::npos)
        << rep["S04"]->offset_detail;
    EXPECT_NE(rep["S01"]->offset_detail.find("unit S04 left out of the pool"), std::string::npos)
        << rep["S01"]->offset_detail;
    for (const std::string id : {"S01", "S03"}) {
        const coeff_set_t* a = nullptr;
        const coeff_set_t* b = nullptr;
        for (const auto& c : clean.publish)
            if (c.sensor_id == id) a = &c;
        for (const auto& c : dirty.publish)
            if (c.sensor_id == id) b = &c;
        ASSERT_TRUE(a && b);
        EXPECT_TRUE(model::FromMsg(*a).offset.covariance.isApprox(
            model::FromMsg(*b).offset.covariance, 1e-9))
            << id;
    }
}

TEST(FitterCore, AReturnToTheStartIsReportedAsRepeatability) {
    FitterCore core(CoreOptions::Defaults());
    core.OnRunEvent(Event("start", "A"));
    int64_t id = 0;
    for (double t : {25.0, -10.0, 10.0, 30.0, 50.0, 70.0})
        core.OnPlateau(Plateau(t, id += 1000), "S01");
    plateau_t back = Plateau(25.3, id += 1000);
    back.gyro_mean_v += 1e-4;  // 5 stated errors of sqrt(2) x 2e-5: not repeatable
    core.OnPlateau(back, "S01");
    const CoreOutput out = core.OnRunEvent(Event("stop", "A"));
    ASSERT_EQ(out.reports.size(), 1u);
    const fit_report_t& r = out.reports[0];
    ASSERT_EQ(r.num_repeats, 1);
    EXPECT_EQ(r.repeats[0].first_plateau_id, 1000);
    EXPECT_EQ(r.repeats[0].second_plateau_id, id);
    // the fit bends toward both visits, so the model step between 25 and 25.3 takes out little:
    // the difference is the 0.1 mV added, within 2 % (the truth's step is subtracted exactly)
    EXPECT_NEAR(r.repeats[0].offset_diff_v, 1e-4, 2e-6);
    EXPECT_NEAR(r.repeats[0].offset_diff_stderr_v, std::sqrt(2.0) * 2e-5, 1e-12);
    EXPECT_NE(r.repeats[0].verdict.find("not repeatable"), std::string::npos)
        << r.repeats[0].verdict;
}

}  // namespace
}  // namespace gyrocal::fitter
