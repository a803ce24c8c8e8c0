// The verdict's honest outcomes on runs with effects OUTSIDE the candidate list: the project's
// rig's own (aging, compressor; more in rig_effects_test.cpp), a step added to its recorded
// gyro_v (sim_run's outside_v), and othersim (an independent rig: its EffectOptions
// drift/periodic/step/warmup2). The truth is used only to check the answers.
//
// Sizes: the 10 s-bin noise floor of the rig is ~0.11 mV and the floor bound (analyze.hpp, step
// 9) ~0.35 mV; every outside effect is made 5-15x the floor in RMS over the run, so that its
// residual is well above the bound (a smaller one is indistinguishable from the slow noise, by
// construction of the bound). What is asserted:
//   - no named offset candidate is added (none of them is the cause);
//   - the outcome is "unexplained residual" (or "partly explained" when a real effect is also
//     there), never "adequate" nor "explained";
//   - the generic feature that explains the held-out data first is the right one (channel time;
//     for the periodic one the period within the grid's resolution and the noise: 15 %).
// Clean runs: "adequate", the false-positive rate measured over 40 seeds and bounded at 2/40 (the
// thresholds claim 4.3 %: AnalysisOptions::ClaimedFalsePositiveRate).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <sstream>
#include <string>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/report.hpp"
#include "tests/processors/analysis/feature_lookup.hpp"
#include "tests/processors/analysis/othersim_run.hpp"
#include "tests/processors/analysis/sim_run.hpp"

namespace gyrocal::analysis {
namespace {

using testing::FirstExplaining;
using testing::MakeSimRun;
using testing::SimRunOptions;

constexpr const char* kOffsetEffects[] = {"temp_rate",  "temp_knot", "hysteresis",
                                          "temp_cubic", "supply",    "warmup"};

bool NamedOffsetAdded(const SensorResult& r) {
    for (const AddedEffect& a : r.added)
        for (const char* e : kOffsetEffects)
            if (a.effect == e) return true;
    return false;
}

struct OutsideCase {
    const char* name;
    std::function<double(double)> offset_v;  // of the time since the start [s]
    // Right correlate: the first generic feature that explains held-out data.
    std::function<bool(const FeatureResult&)> right;
};

bool TimeShaped(const FeatureResult& f) {
    return f.channel == "time" || f.channel == "time since power-on";
}

double PeriodOf(const FeatureResult& f) {
    const auto p = f.detail.find("period ");
    return p == std::string::npos ? NAN : std::stod(f.detail.substr(p + 7));
}

void RunOutside(const OutsideCase& c, int seeds) {
    int honest = 0;
    for (int seed = 1; seed <= seeds; ++seed) {
        SimRunOptions o;
        o.seed = 600 + seed;
        o.outside_v = c.offset_v;
        const SensorResult r = Analyze(MakeSimRun(o).run);
        SCOPED_TRACE(std::string(c.name) + " seed " + std::to_string(o.seed) + "\n" +
                     FormatReport(r));
        const FeatureResult* top = r.features.empty() ? nullptr : &r.features[0];
        std::printf(
            "[ verdict ] %s seed %d: %s, residual/bound %.2f, top feature %s z %.2f "
            "leaves %.2f of the held-out residual\n",
            c.name, static_cast<int>(o.seed), ToString(r.outcome), r.excess_ratio,
            top ? top->feature.c_str() : "-", top ? top->heldout_z : NAN,
            top ? top->heldout_after_rms_v / r.heldout_residual_rms_v : NAN);
        EXPECT_FALSE(NamedOffsetAdded(r)) << r.headline;
        EXPECT_TRUE(r.outcome == Outcome::kUnexplained || r.outcome == Outcome::kPartlyExplained)
            << ToString(r.outcome);
        const FeatureResult* f = FirstExplaining(r);
        ASSERT_NE(f, nullptr);
        EXPECT_TRUE(c.right(*f)) << f->feature << " " << f->detail;
        if (!NamedOffsetAdded(r) && r.outcome == Outcome::kUnexplained && c.right(*f)) ++honest;
    }
    std::printf("[ verdict ] outside effect %-16s honest verdict with the right correlate %d/%d\n",
                c.name, honest, seeds);
}

constexpr int kSeeds = 4;

// A slow drift, a periodic disturbance and a warm-up slower than the search grid are the rig's
// own effects now (aging, compressor, warmup_tau_s=4000): rig_effects_test.cpp. A step has no
// physical counterpart in the rig, so it stays here as an offset added to the recorded samples.
TEST(Outside, OffsetStep) {
    // 1.5 mV from 2500 s on (RMS about the mean ~0.75 mV).
    RunOutside({"step 1.5 mV", [](double t) { return t >= 2500.0 ? 1.5e-3 : 0.0; },
                [](const FeatureResult& f) { return f.channel == "time"; }},
               kSeeds);
}

// A static temperature shape no candidate has in its form: the offset bends away at the hot end,
// 6 mV x exp((T - 70 degC) / 8 degC) (6 mV at 70 degC, 0.5 mV at 50 degC; the analysis
// benchmark's "hot-end exp bend"). A cubic alone is but the bend's projection on dT^3; one knot of
// a cubic spline (temp_knot, alone or beyond the cubic) follows the bend. So temp_knot is named,
// with or without temp_cubic, nothing else is, and what is left on the held-out bins is within the
// floor bound (floor^2 (1 + 9 k^2) + 9 prediction^2: 3 sigma of the run's own
// noise, outcome.cpp). Before temp_knot the cubic was named alone in 8 of 10 benchmark runs
// (held-out error 2.3x the truth's); then, with the rule against it, nothing was named and the unit
// was left uncompensated (5.4x).
TEST(Outside, HotEndBendIsFollowedByTheSplineKnot) {
    int followed = 0;
    for (int seed = 1; seed <= kSeeds; ++seed) {
        SimRunOptions o;
        o.seed = 600 + seed;
        o.outside_channels_v = [](const testing::OutsideInputs& in) {
            return 6e-3 * std::exp((in.temp_c - 70.0) / 8.0);
        };
        const SensorResult r = Analyze(MakeSimRun(o).run);
        SCOPED_TRACE("hot-end bend seed " + std::to_string(o.seed) + "\n" + FormatReport(r));
        std::vector<std::string> added;
        for (const AddedEffect& a : r.added) added.push_back(a.effect);
        const bool knot = std::count(added.begin(), added.end(), "temp_knot") == 1;
        const bool cubic = std::count(added.begin(), added.end(), "temp_cubic") == 1;
        EXPECT_TRUE(knot && added.size() == 1u + cubic) << r.headline;
        // A single knot does not follow an exponential exactly: a 10 degC band may still stand
        // out (partly explained), but the run as a whole is explained within the bound.
        EXPECT_TRUE(r.outcome == Outcome::kExplained || r.outcome == Outcome::kPartlyExplained)
            << r.headline;
        EXPECT_LE(r.excess_ratio, 1.0) << r.headline;
        if (knot && added.size() == 1u + cubic && r.excess_ratio <= 1.0) ++followed;
    }
    std::printf(
        "[ verdict ] hot-end bend: temp_knot (+ temp_cubic), explained within the bound %d/%d\n",
        followed, kSeeds);
}

TEST(Verdict, CleanRunsAreAdequate) {
    // 40 seeds; asserted bound 2/40 (5 %) for any outcome other than adequate.
    const int seeds = 40;
    int not_adequate = 0;
    double max_drop = -INFINITY;
    std::string max_drop_feature;
    for (int seed = 1; seed <= seeds; ++seed) {
        SimRunOptions o;
        o.seed = 700 + seed;
        const SensorResult r = Analyze(MakeSimRun(o).run);
        // The margin to min_feature_drop: the largest fraction of the held-out squared residual
        // any generic feature removed on a clean run.
        for (const FeatureResult& f : r.features)
            if (std::isfinite(f.heldout_drop) && f.heldout_drop > max_drop)
                max_drop = f.heldout_drop, max_drop_feature = f.feature + " [" + f.channel + "]";
        const FeatureResult* top = r.features.empty() ? nullptr : &r.features[0];
        std::printf(
            "[ verdict ] clean seed %d: %s, residual/bound %.2f, top feature %s z %.2f "
            "leaves %.2f of the held-out residual\n",
            700 + seed, ToString(r.outcome), r.excess_ratio, top ? top->feature.c_str() : "-",
            top ? top->heldout_z : NAN,
            top ? top->heldout_after_rms_v / r.heldout_residual_rms_v : NAN);
        if (r.outcome != Outcome::kAdequate) {
            ++not_adequate;
            std::printf("%s", FormatReport(r).c_str());
        } else {
            EXPECT_EQ(r.verdict.rfind("no missing effect: adequate", 0), 0u) << r.verdict;
            EXPECT_LE(r.excess_ratio, 1.0);
        }
    }
    std::printf("[ verdict ] clean runs: %d/%d not adequate (%.1f %%)\n", not_adequate, seeds,
                100.0 * not_adequate / seeds);
    std::printf(
        "[ verdict ] clean runs: largest held-out fraction removed by a feature %.3f (%s); the "
        "null of the run's own noise decides (claimed false-positive rate %.1f %%)\n",
        max_drop, max_drop_feature.c_str(),
        100.0 * AnalysisOptions::Defaults().ClaimedFalsePositiveRate());
    // The thresholds claim 4.3 % (ClaimedFalsePositiveRate): 1.7 expected in 40; 2 allowed.
    EXPECT_LE(not_adequate, 2);
}

TEST(Verdict, RunAtOneTemperatureIsNotTestable) {
    SimRunOptions o;
    o.seed = 801;
    o.setpoints_c = {25.0, 25.0};
    const SensorResult r = Analyze(MakeSimRun(o).run);
    SCOPED_TRACE(FormatReport(r));
    EXPECT_EQ(r.outcome, Outcome::kNotTestable);
    EXPECT_EQ(r.verdict.rfind("not testable", 0), 0u) << r.verdict;
    for (const char* e : {"temp_rate", "hysteresis", "temp_cubic"}) {
        EXPECT_NE(std::find(r.untested.begin(), r.untested.end(), e), r.untested.end()) << e;
        EXPECT_NE(r.verdict.find(e), std::string::npos) << e;
    }
    EXPECT_GT(r.untested.size(), 3u);
    EXPECT_EQ(r.to_test.size(), r.untested.size());
    EXPECT_TRUE(r.added.empty());
}

// The simulated rig's run (seed `seed`) with the one effect `effect` of size `value` on, analysed.
SensorResult AnalyzeRigWith(uint64_t seed, const std::string& effect, double value) {
    SimRunOptions o;
    o.seed = seed;
    sim::SetEffect(o.effects, effect, value);
    return Analyze(MakeSimRun(o).run);
}

TEST(Verdict, ExplainedWhenTheEffectIsACandidate) {
    // A warm-up inside the grid (the rig's own, 2 mV): named and the residual at the floor.
    const SensorResult r = AnalyzeRigWith(802, "warmup", 2e-3);
    SCOPED_TRACE(FormatReport(r));
    EXPECT_EQ(r.outcome, Outcome::kExplained);
    EXPECT_EQ(r.verdict.rfind("missing effect: warmup, explained", 0), 0u) << r.verdict;
}

TEST(Verdict, PartlyExplainedWhenACandidateAndAnOutsideEffectAreBothThere) {
    SimRunOptions o;
    o.seed = 803;
    sim::SetEffect(o.effects, "hysteresis", 2e-3);
    sim::SetEffect(o.effects, "compressor", 0.8e-3);  // outside the list: 0.8 mV at 700 s
    sim::SetEffect(o.effects, "compressor_period_s", 700.0);
    const SensorResult r = Analyze(MakeSimRun(o).run);
    SCOPED_TRACE(FormatReport(r));
    EXPECT_EQ(r.outcome, Outcome::kPartlyExplained);
    ASSERT_EQ(r.added.size(), 1u);
    EXPECT_EQ(r.added[0].effect, "hysteresis");
    const FeatureResult* f = FirstExplaining(r);
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f->feature, "periodic");
}

// A candidate and a time shape the data cannot tell apart: the supply rises steadily, 0.2 V over
// the run (~4700 s), and the offset follows it at 0.01 V/V (2 mV end to end, RMS ~5x the 10 s-bin
// floor). The recorded supply is that ramp plus the rig's 0.5 mV measurement noise (~0.016 mV in
// a 10 s bin mean), so the supply term and a linear drift in time are the same regressor to within
// 0.02 % of its range: on the held-out bins neither adds to the other and their squared errors
// are equal within the noise (displace.cpp's twin rule). The verdict must say so ("ambiguous:
// supply vs time since start"), not name supply alone.
TEST(Verdict, SupplyThatDriftsWithTimeIsAmbiguousWithADrift) {
    for (uint64_t seed : {805u, 806u, 807u, 808u}) {
        SimRunOptions o;
        o.seed = seed;
        testing::SimRun sim = MakeSimRun(o);
        std::mt19937_64 rng(seed);
        std::normal_distribution<double> noise_v(0.0, 0.5e-3);
        const int64_t start_utime = sim.run.samples.front().utime;
        for (GyroSample& g : sim.run.samples) {
            const double rise_v = 0.2 * (g.utime - start_utime) * 1e-6 / 4700.0;
            g.supply_v = 5.0 + rise_v + noise_v(rng);
            g.gyro_v += 0.01 * rise_v;
        }
        const SensorResult r = Analyze(sim.run);
        SCOPED_TRACE("seed " + std::to_string(seed) + "\n" + FormatReport(r));
        std::printf("[ verdict ] supply drifting with time, seed %d: %s\n", static_cast<int>(seed),
                    r.verdict.c_str());
        EXPECT_EQ(r.outcome, Outcome::kAmbiguous) << ToString(r.outcome);
        EXPECT_NE(r.verdict.find("ambiguous: supply vs time since start [time]"), std::string::npos)
            << r.verdict;
        EXPECT_FALSE(NamedOffsetAdded(r)) << r.verdict;
    }
}

TEST(Verdict, JsonCarriesTheOutcomeAndTheDiagnostics) {
    // GIVEN the rig's null ageing at 2 mV/h (outside the candidate list), nothing else
    const SensorResult r = AnalyzeRigWith(804, "aging", 2e-3);
    SCOPED_TRACE(FormatReport(r));
    const nlohmann::json j = ToJson(r);
    // THEN the verdict is the truth's: no candidate named, an unexplained residual traced to time
    EXPECT_EQ(j["outcome"], "unexplained residual");
    EXPECT_EQ(j["headline"], r.verdict);
    EXPECT_TRUE(j["added"].empty()) << j["added"].dump();
    const FeatureResult* f = FirstExplaining(r);
    ASSERT_NE(f, nullptr);
    EXPECT_TRUE(TimeShaped(*f)) << f->feature;
    // AND the JSON carries the figures that say so
    EXPECT_TRUE(j["floor_bound_rms_v"].is_number());
    EXPECT_GT(j["excess_ratio"].get<double>(), 0.0);
    ASSERT_FALSE(j["features"].empty());
    for (const char* k : {"feature", "channel", "corr", "heldout_z", "null_z", "null_threshold",
                          "explains_heldout"})
        EXPECT_TRUE(j["features"][0].contains(k)) << k;
    for (const char* k : {"lag1_autocorr", "trend_v_per_h", "period_s", "by_time_s", "by_temp_c"})
        EXPECT_TRUE(j["residual"].contains(k)) << k;
    for (const char* k : {"slow_noise_k", "surrogates", "feature_null_threshold",
                          "window_null_threshold", "claimed_false_positive_rate"})
        EXPECT_TRUE(j["thresholds_from_run"].contains(k)) << k;
    EXPECT_EQ(j["thresholds_from_run"]["surrogates"], AnalysisOptions::Defaults().surrogates);
    // AND the residual's trend is the drift: 2 mV/h within 4 of its standard errors (the trend's
    // autocorrelation-robust error, from the noise) plus 30 % for what the declared model's
    // temperature terms absorb of a drift on these setpoints (time and temperature are partly
    // collinear over one run).
    const double trend = j["residual"]["trend_v_per_h"].get<double>();
    const double se = trend / j["residual"]["trend_z"].get<double>();
    EXPECT_NEAR(trend, 2e-3, 4.0 * std::fabs(se) + 0.3 * 2e-3);
}

TEST(BadInput, VerdictOptionsAreRefusedWithTheirName) {
    SimRunOptions so;
    so.seed = 805;
    const SensorRun run = MakeSimRun(so).run;
    auto refused = [&](const char* name, const std::function<void(AnalysisOptions&)>& set) {
        AnalysisOptions o;
        set(o);
        EXPECT_NE(o.Validate().find(name), std::string::npos) << name << ": " << o.Validate();
        EXPECT_THROW(Analyze(run, o), std::invalid_argument) << name;
    };
    for (double v : {11.0, kNan})
        refused("slow_noise_floor_ratio",
                [v](AnalysisOptions& o) { o.slow_noise_floor_ratio = v; });
    for (double v : {-0.1, 1.0, kNan})
        refused("min_feature_drop", [v](AnalysisOptions& o) { o.min_feature_drop = v; });
    for (double v : {0.0, 0.5, kNan}) {
        refused("feature_fpr", [v](AnalysisOptions& o) { o.feature_fpr = v; });
        refused("window_fpr", [v](AnalysisOptions& o) { o.window_fpr = v; });
        refused("warmup_fpr", [v](AnalysisOptions& o) { o.warmup_fpr = v; });
    }
    for (int v : {0, 19, 10001})
        refused("surrogates", [v](AnalysisOptions& o) { o.surrogates = v; });
    for (double v : {-0.1, 1.1, kNan})
        refused("max_untested_fraction", [v](AnalysisOptions& o) { o.max_untested_fraction = v; });
    refused("early_block_s", [](AnalysisOptions& o) { o.early_block_s = 1.0; });
}

// ---- othersim: an independent rig ------------------------------------------------------------

// One unit's othersim run through the CSV reader into the analysis input (othersim_run.hpp). Its
// curve made quadratic (no cubic, no cold bend) and its own warm-up off, so that none of the
// candidates is really there; the temperature line's lag is a real temp_rate effect and may be
// found.
SensorRun OthersimRun(uint64_t seed, const othersim::EffectOptions& e) {
    othersim::Options o = othersim::Options::QuickReturnToStart(420.0);
    o.seed = seed;
    o.spread.cubic_sd_v = 0.0;
    o.spread.cold_bend_sd_v = 0.0;
    o.effects = e;
    o.effects.warmup_v = 0.0;
    return testing::MakeOthersimRun(o).run;
}

void RunOthersim(const char* name, const othersim::EffectOptions& e,
                 const std::function<bool(const FeatureResult&)>& right) {
    for (uint64_t seed : {11u, 12u}) {
        const SensorResult r = Analyze(OthersimRun(seed, e));
        SCOPED_TRACE(std::string(name) + " seed " + std::to_string(seed) + "\n" + FormatReport(r));
        std::printf("[ verdict ] othersim %s seed %d: %s\n", name, static_cast<int>(seed),
                    r.headline.c_str());
        for (const AddedEffect& a : r.added)
            EXPECT_TRUE(a.effect == "temp_rate") << "named " << a.effect;
        EXPECT_TRUE(r.outcome == Outcome::kUnexplained || r.outcome == Outcome::kPartlyExplained)
            << ToString(r.outcome);
        const FeatureResult* f = FirstExplaining(r);
        ASSERT_NE(f, nullptr);
        EXPECT_TRUE(right(*f)) << f->feature << " " << f->detail;
    }
}

TEST(OutsideOthersim, Drift) {
    othersim::EffectOptions e;
    e.drift_v_per_h = 3e-3;
    RunOthersim("drift", e, TimeShaped);
}

TEST(OutsideOthersim, Periodic) {
    othersim::EffectOptions e;
    e.periodic_v = 1e-3;
    e.periodic_s = 900.0;
    RunOthersim("periodic", e, [](const FeatureResult& f) {
        return f.feature == "periodic" && std::fabs(PeriodOf(f) / 900.0 - 1) < 0.15;
    });
}

TEST(OutsideOthersim, Step) {
    othersim::EffectOptions e;
    e.step_v = 2e-3;
    e.step_at_s = 3000.0;
    RunOthersim("step", e, [](const FeatureResult& f) { return f.channel == "time"; });
}

// A one-time shift early in the run (1.5 mV from 1100 s on, the CSV says nothing of it): the
// stretch before it looks like a transient after power-on, and the warm-up, which blocked
// cross-validation cannot check (localized.hpp), was named for it (3 of 10 othersim runs of the
// benchmark's "one-time shift"). The step rule weighs every warm-up against a step at a
// searched time: not named, and the step is what is left.
TEST(OutsideOthersim, EarlyStepIsNotAWarmup) {
    othersim::EffectOptions e;
    e.step_v = 1.5e-3;
    e.step_at_s = 1100.0;
    // What is left is time-shaped (the step, or a slow transient standing in for it).
    RunOthersim("early step", e, TimeShaped);
    // Where the warm-up passed its own check (z2, size, its localized prediction), it was weighed
    // against the step and the step found where it is: the step's time is searched on a grid of
    // about 22 s (every 200th part of the run) over 10 s bins, so within 60 s of the truth. Seed 11
    // gets there (warmup(436) passes its check); on seed 12 the warm-up's z2 stays below min_z2.
    int weighed = 0;
    for (uint64_t seed : {11u, 12u}) {
        const SensorResult r = Analyze(OthersimRun(seed, e));
        for (const std::string& s : r.not_attributed) {
            if (s.rfind("warmup", 0) != 0) continue;
            const std::string key = "a one-time step at ";
            const size_t at = s.find(key);
            ASSERT_NE(at, std::string::npos) << s;
            EXPECT_NEAR(std::stod(s.substr(at + key.size())), 1100.0, 60.0) << s;
            ++weighed;
        }
    }
    EXPECT_GE(weighed, 1);
}

TEST(OutsideOthersim, SecondSlowWarmup) {
    othersim::EffectOptions e;
    e.warmup2_v = 5e-3;
    e.warmup2_tau_s = 5000.0;
    RunOthersim("warmup2", e, TimeShaped);
}

// One effect masking another: a power-on warm-up of -12 mV (tau 300 s) and a supply sensitivity of
// 0.05 V/V on othersim (its curve quadratic, so these two are all there is besides the thermometer
// lag's temp_rate). Chosen before the warm-up, the supply's forward test sees the transient as
// noise and its blocked CV cannot predict it (cv_gain -1.5, rejected) while the same regressor,
// as a generic feature, explained the held-out residual: the benchmark's "warm-up + supply" on
// othersim had a median held-out error 5.5x the truth's. The candidates are now tested again with
// the warm-up in the model, on the bins after it has decayed (offset_step.cpp). Asserted: both
// named, nothing the truth lacks, the supply coefficient within 4 of its standard errors of 0.05
// (the estimate's own noise; 4 sigma for 4 seeds). Without the second choice 0/4 seeds name the
// supply here; with it 4/4, and 32/32 over warm-ups of -12, -8, -4 and 4 mV and supplies of 0.02
// and 0.05 V/V (checked once, 2026-11-29).
TEST(MaskedOthersim, AWarmupDoesNotHideTheSupply) {
    int both = 0;
    for (uint64_t seed : {11u, 12u, 13u, 14u}) {
        othersim::Options o = othersim::Options::QuickReturnToStart(420.0);
        o.seed = seed;
        o.spread.cubic_sd_v = 0.0;
        o.spread.cold_bend_sd_v = 0.0;
        o.effects.warmup_v = -12e-3;
        o.effects.warmup_tau_s = 300.0;
        o.effects.supply_v_per_v = 0.05;
        const SensorResult r = Analyze(testing::MakeOthersimRun(o).run);
        SCOPED_TRACE("seed " + std::to_string(seed) + "\n" + FormatReport(r));
        bool warm = false, supply = false;
        for (const AddedEffect& a : r.added) {
            EXPECT_TRUE(a.effect == "warmup" || a.effect == "supply" || a.effect == "temp_rate")
                << "named " << a.effect;
            warm = warm || a.effect == "warmup";
            if (a.effect != "supply") continue;
            supply = true;
            EXPECT_NEAR(a.coefficient, 0.05, 4.0 * a.stderr_) << "+- " << a.stderr_;
        }
        EXPECT_TRUE(warm) << r.headline;
        EXPECT_TRUE(supply) << r.headline;
        both += warm && supply;
    }
    std::printf("[ verdict ] othersim warm-up -12 mV + supply 0.05 V/V: both named %d/4\n", both);
}

// The published set is for prediction (analysis::CarryForPrediction): where the verdict does not
// name temp_cubic but the unit's curve has one (othersim's own curve: a cubic part of 1.5 mV at
// +-50 degC (1 sigma) and a cold-end bend), dT^3 is carried when it lowers the held-out error,
// and the set carrying it is closer to the unit's true curve (at the measured temperature, over
// the still bins) than the set without it. No tolerance is needed for "closer": it compares two
// distances to the same truth on the same bins; the benchmark found the cubic better on the
// held-out run in 25 of 40 such seeds and worse in none (docs/closing-the-loop.md).
TEST(Prediction, TheCubicIsCarriedWhereTheCurveHasOneAndBringsTheSetCloserToTheTruth) {
    int carried = 0, closer = 0, not_named = 0;
    for (uint64_t seed = 31; seed <= 38; ++seed) {
        othersim::Options o = othersim::Options::QuickReturnToStart(420.0);
        o.seed = seed;
        o.effects.warmup_v = 0.0;  // the curve alone
        const testing::OthersimRun m = testing::MakeOthersimRun(o);
        const AnalysisOptions ao = AnalysisOptions::Defaults();
        SensorResult r = Analyze(m.run, ao);
        if (!r.extended_offset) continue;
        bool named = false;
        for (const AddedEffect& a : r.added) named = named || a.effect == "temp_cubic";
        if (named) continue;
        ++not_named;
        const BinnedRun b(m.run, ao.bins);
        const model::Model before = *r.extended_offset;
        const std::string note = CarryForPrediction(b, ao, "temp_cubic", "dT^3", r);
        SCOPED_TRACE("seed " + std::to_string(seed) + ": " + note);
        const std::vector<std::string>& t = r.extended_offset->term_names;
        if (std::find(t.begin(), t.end(), "dT^3") == t.end()) continue;
        ++carried;
        EXPECT_NE(note.find("carried for prediction"), std::string::npos);
        EXPECT_EQ(r.notes.back(), note);
        // The truth's bin means on the same bins.
        Eigen::VectorXd truth(static_cast<Eigen::Index>(b.size()));
        size_t k = 0;
        for (size_t i = 0; i < b.size(); ++i) {
            const Bin& bin = b.bins()[i];
            while (k < m.run.samples.size() && m.run.samples[k].utime < bin.start_utime) ++k;
            double sum = 0;
            int n = 0;
            for (size_t j = k; j < m.run.samples.size() && m.run.samples[j].utime < bin.end_utime;
                 ++j)
                sum += m.truth_offset_v[j], ++n;
            truth[static_cast<Eigen::Index>(i)] = n ? sum / n : NAN;
        }
        const double d_before = (b.Values(before) - truth).norm();
        const double d_after = (b.Values(*r.extended_offset) - truth).norm();
        EXPECT_LT(d_after, d_before);
        closer += d_after < d_before;
    }
    std::printf(
        "[ verdict ] othersim curve, temp_cubic not named in %d of 8: dT^3 carried %d, "
        "closer to the truth %d\n",
        not_named, carried, closer);
    // Most units' curves carry a cubic part above the noise: the rule must act, not stay idle.
    EXPECT_GE(carried, not_named / 2);
}

}  // namespace
}  // namespace gyrocal::analysis
