// Model discovery on simulated runs with an undeclared effect switched on in the rig (announced to
// nothing downstream: the analysis gets only what a recorder would have stored). The rig's truth
// is used here only to check the answers.
//
// Run: 1 unit, 25 degC start, setpoints -10, 50, 10, 70, 30 (ramps both ways through shared
// temperatures), 6 degC/min ramps, package tau 60 s, dwell 420 s, +-90 deg rotations; ~4700 s of
// simulated time, ~0.4 s to simulate. Effect sizes are a few times the 10 s-bin noise floor
// (~0.018 deg/s = 0.11 mV): temp_rate 1e-4 V/(degC/min) (0.6 mV at 6 degC/min), hysteresis 1 mV
// apart, temp_cubic 2e-8 V/K^3 (1.8 mV at 45 K), supply 0.05 V/V (0.5 mV per 10 mV of drift),
// warmup 2 mV, sf_asymmetry 2 %.
//
// Tolerances on a coefficient: 4 reported standard errors (the analysis' autocorrelation-robust
// stderr; 4 sigma keeps a correct estimate inside with probability > 0.9999 per seed) plus a
// stated model-mismatch allowance where the analysis' regressor is not exactly the rig's:
//   temp_rate  5 %: the measured-temperature difference over 2 bins vs the die's instantaneous rate
//              (they differ at ramp corners), plus the temperature sensor lag 0.1 s * |dV/dT|;
//   hysteresis 5 %: the rig's branch is a play operator of width 2 degC on the die, continuous in
//              [-1, 1]; the analysis' is +-1 from width 1 degC on the measured temperature;
//   warmup    10 %: tau comes from a grid (ratio 1.21 between points) and trades against amplitude;
//   sf_asymmetry 3 %: the rig scales S(T) (which varies ~2 % over the range), the term is constant.
// Error after, on the held-out stretch: what a perfect model would leave there is the white
// scatter of 10 s bins (the floor, from inside plateau windows) plus the slow noise, which the
// floor cannot see (bias instability and rate random walk in 10 s bin means:
// sim::SlowNoiseBinVariance, ~0.018 deg/s at the defaults, as large as the floor); fitting the
// coefficients on the data before the stretch adds their prediction error (the analysis'
// prediction_rms from the fit's covariance). The slow noise and the prediction error are each
// nearly one shape over the stretch (the 1000 s component; one coefficient error), one degree of
// freedom, so a 3-sigma bound is 9x their variance:
//   after^2 < floor^2 + 9 (slow^2 + prediction^2).
// A missing or wrong term leaves the declared model's error, several times more. "Far below
// before": over all still data, the extended model's residual RMS is below 0.7x the declared
// model's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/report.hpp"
#include "producers/sim/noise.hpp"
#include "tests/processors/analysis/sim_run.hpp"

namespace gyrocal::analysis {
namespace {

using testing::MakeSimRun;
using testing::SimRun;
using testing::SimRunOptions;

bool Added(const SensorResult& r, const std::string& effect) {
    for (const AddedEffect& a : r.added)
        if (a.effect == effect) return true;
    return false;
}

const AddedEffect* Find(const SensorResult& r, const std::string& effect) {
    for (const AddedEffect& a : r.added)
        if (a.effect == effect) return &a;
    return nullptr;
}

struct EffectCase {
    const char* name;  // rig effect name (sim::SetEffect)
    double value;
    double allowance;  // relative model-mismatch allowance (see the header)
    // The coefficient the analysis should find, from the rig's truth.
    std::function<double(const SimRun&)> truth;
};

double LagBias(const SimRun& s) {
    // |dV/dT| over the range times the sensor lag: the offset seen through a lagging thermometer.
    const auto& o = s.truth.offset_coeffs;
    return (std::fabs(o[1]) + 2.0 * std::fabs(o[2]) * 50.0) * s.config.thermal.sensor_tau_s;
}

double AfterBoundDps(const SensorResult& r, const SimRun& s) {
    const double slow2 = sim::SlowNoiseBinVariance(s.config.noise, r.bin_s, s.duration_s);
    return std::sqrt(r.floor_rate_rms_dps * r.floor_rate_rms_dps +
                     9.0 * (slow2 + r.prediction_rms_dps * r.prediction_rms_dps));
}

void RunEffect(const EffectCase& c, int seeds, bool offset_effect) {
    int hits = 0, extra = 0;
    for (int seed = 1; seed <= seeds; ++seed) {
        SimRunOptions o;
        o.seed = 100 + seed;
        sim::SetEffect(o.effects, c.name, c.value);
        const SimRun s = MakeSimRun(o);
        const SensorResult r = Analyze(s.run);
        SCOPED_TRACE(std::string(c.name) + " seed " + std::to_string(o.seed) + "\n" +
                     FormatReport(r));
        if (!Added(r, c.name)) {
            std::printf("[ analysis ] missed %s on seed %llu:\n%s", c.name,
                        static_cast<unsigned long long>(o.seed), FormatReport(r).c_str());
            continue;
        }
        ++hits;
        if (r.added.size() > 1) ++extra;
        const AddedEffect* a = Find(r, c.name);
        const double truth = c.truth(s);
        double tol = 4.0 * a->stderr_ + c.allowance * std::fabs(truth);
        if (std::string(c.name) == "temp_rate") tol += LagBias(s);
        EXPECT_NEAR(a->coefficient, truth, tol) << a->unit;
        if (offset_effect) {
            EXPECT_LT(r.error_after.rate_rms_dps, AfterBoundDps(r, s));
            EXPECT_LT(r.residual_all_extended_rms_v, 0.7 * r.residual_all_rms_v);
        } else {
            EXPECT_LT(r.sens_rel_rms_after, 0.5 * r.sens_rel_rms_before);
            EXPECT_LT(r.sens_chi2_dof_after, 3.0);
        }
    }
    std::printf("[ analysis ] effect %-12s = %-8g hit rate %d/%d, runs with an extra effect %d\n",
                c.name, c.value, hits, seeds, extra);
    // At these sizes a miss is not expected at all; allow one in `seeds` for the unlucky draw.
    EXPECT_GE(hits, seeds - 1);
    EXPECT_LE(extra, 2);
}

constexpr int kSeeds = 8;

TEST(Discovery, TempRate) {
    RunEffect({"temp_rate", 1e-4, 0.05, [](const SimRun&) { return 1e-4 * 60.0; }}, kSeeds, true);
}
TEST(Discovery, Hysteresis) {
    RunEffect({"hysteresis", 1e-3, 0.05, [](const SimRun&) { return 0.5e-3; }}, kSeeds, true);
}
TEST(Discovery, TempCubic) {
    RunEffect({"temp_cubic", 2e-8, 0.0, [](const SimRun&) { return 2e-8; }}, kSeeds, true);
}
TEST(Discovery, Supply) {
    RunEffect({"supply", 0.05, 0.0, [](const SimRun&) { return 0.05; }}, kSeeds, true);
}
TEST(Discovery, Warmup) {
    RunEffect({"warmup", 2e-3, 0.10, [](const SimRun&) { return 2e-3; }}, kSeeds, true);
}
TEST(Discovery, SfAsymmetry) {
    RunEffect({"sf_asymmetry", 0.02, 0.03,
               [](const SimRun& s) { return 0.5 * 0.02 * s.truth.sensitivity_coeffs[0]; }},
              kSeeds, false);
}

TEST(Discovery, TwoEffectsAtOnceAreBothFound) {
    const std::vector<std::pair<const char*, const char*>> pairs = {{"temp_rate", "supply"},
                                                                    {"hysteresis", "temp_cubic"}};
    const std::map<std::string, double> size = {
        {"temp_rate", 1e-4}, {"supply", 0.05}, {"hysteresis", 1e-3}, {"temp_cubic", 2e-8}};
    for (const auto& [a, b] : pairs) {
        int both = 0;
        const int seeds = 3;
        for (int seed = 1; seed <= seeds; ++seed) {
            SimRunOptions o;
            o.seed = 200 + seed;
            sim::SetEffect(o.effects, a, size.at(a));
            sim::SetEffect(o.effects, b, size.at(b));
            const SensorResult r = Analyze(MakeSimRun(o).run);
            SCOPED_TRACE(FormatReport(r));
            EXPECT_TRUE(Added(r, a));
            EXPECT_TRUE(Added(r, b));
            if (Added(r, a) && Added(r, b)) ++both;
        }
        std::printf("[ analysis ] %s + %s: both found in %d/%d\n", a, b, both, seeds);
    }
}

// A thermometer lagging the die by L (the rig's sensor_tau_s: first order, so T_die = T_meas +
// L dT_meas/dt) makes the truth's quadratic offset f(T_die) read f(T_meas) + f'(T_meas) L dT/dt +
// O(L^2): temp_rate takes (o1 + 2 o2 (t0 - 25)) L, thermometer_lag's dT x dT/dt exactly 2 o2 L
// [V/(degC^2/s)] (o2 the truth's curvature, independent of t0). With the rig's default 15 s lag
// the analysis must name it with that coefficient; with 0.1 s (the control, the same units and
// noise) the product is 150x smaller, far below the floor, and must not be named.
// Tolerance: 4 reported standard errors plus a 10 % allowance: the rate tracker's dT/dt (time
// constant searched on temp_rate's grid, >= 2 s) is not the instantaneous rate of the thermometer
// at the ramps' corners, and the O(L^2) term f''(T) L^2 (dT/dt)^2 / 2 = o2 L^2 (dT/dt)^2 is a
// |dT/dt|^2 shape no term has (0.2 mV at 6 degC/min for o2 = 3 uV/K^2: it biases the product's
// coefficient by what of it correlates with dT x dT/dt).
// Named: on every seed whose product is plainly above what the analysis can see (its RMS over
// the ramps >= 2x the 10 s-bin floor of 0.11 mV: (c) needs the lag's size above 1x the floor
// over all bins, and about half of the product's ramp RMS is left once the quadratic and dT/dt
// are projected out; the units' curvatures are drawn, some are small): at most one such seed may
// miss it (the backward re-test may drop a term near z^2 25).
TEST(Discovery, ThermometerLagIsNamedWithTwiceTheCurvatureTimesTheLag) {
    const double lag_s = sim::RigConfig::Defaults().thermal.sensor_tau_s;
    ASSERT_EQ(lag_s, 15.0);
    int visible = 0, named_visible = 0, named_control = 0;
    const int seeds = 6;
    for (int seed = 301; seed < 301 + seeds; ++seed) {
        for (const double tau_s : {lag_s, 0.1}) {
            SimRunOptions o;
            o.seed = static_cast<uint64_t>(seed);
            o.sensor_tau_s = tau_s;
            const SimRun s = MakeSimRun(o);
            AnalysisOptions opts = AnalysisOptions::Defaults();
            opts.thermometer_lag_candidate = true;  // off by default (AnalysisOptions)
            const SensorResult r = Analyze(s.run, opts);
            SCOPED_TRACE("seed " + std::to_string(seed) + ", sensor lag " + std::to_string(tau_s) +
                         " s\n" + FormatReport(r));
            const double truth = 2.0 * s.truth.offset_coeffs[2] * tau_s;
            // 6 degC/min ramps over +-40 degC about t0: |dT x dT/dt| ~ 40 x 0.1 at the ends, RMS
            // over a ramp (uniform in dT) 0.1 x 40 / sqrt(3).
            const double effect_rms_v = std::fabs(truth) * 0.1 * 40.0 / std::sqrt(3.0);
            const AddedEffect* a = Find(r, "thermometer_lag");
            std::printf(
                "[ analysis ] thermometer lag %g s seed %d: truth 2 o2 L %.3e V/(degC^2/s) "
                "(effect ~%.3f mV); named %s %.3e +- %.3e; added %zu terms\n",
                tau_s, seed, truth, effect_rms_v * 1e3, a ? a->term.c_str() : "no",
                a ? a->coefficient : NAN, a ? a->stderr_ : NAN, r.added.size());
            if (tau_s != lag_s) {
                if (a) ++named_control;
                EXPECT_EQ(a, nullptr) << "named without a lag";
                continue;
            }
            const bool big = effect_rms_v >= 2.0 * 0.11e-3;
            visible += big;
            if (!a) continue;
            named_visible += big;
            EXPECT_NEAR(a->coefficient, truth, 4.0 * a->stderr_ + 0.10 * std::fabs(truth));
            EXPECT_NE(a->term.find("dT*dTdt("), std::string::npos) << a->term;
        }
    }
    std::printf(
        "[ analysis ] thermometer_lag named on %d of %d seeds whose product is visible "
        "(15 s lag); on %d of %d with the 0.1 s lag\n",
        named_visible, visible, named_control, seeds);
    EXPECT_GE(visible, 3);  // the test means something
    EXPECT_GE(named_visible, visible - 1);
    EXPECT_EQ(named_control, 0);
}

// The `five` profile ramps down once, and with the rig's 15 s thermometer lag every run carries
// a temp_rate effect: hysteresis and temp_rate are nearly collinear there (projected correlation
// ~0.9). A collinear pair that passes as a pair is added whole, and the verdict must still say
// that the data cannot tell the two apart (never name one of them as the cause), with the
// measurement that would separate them. Seeds 201-203 (those of the held-out ramp test, where
// seed 203 takes this path): asserted on every seed that takes it, and that one seed at least does.
TEST(Discovery, CollinearPairIsKeptWholeAndTheVerdictStillSaysAmbiguous) {
    int joint_runs = 0;
    for (int seed = 201; seed <= 203; ++seed) {
        SimRunOptions o;
        o.seed = static_cast<uint64_t>(seed);
        sim::SetEffect(o.effects, "hysteresis", 1e-3);
        o.setpoints_c = {-40.0, -10.0, 25.0, 55.0, 85.0};  // sequencer profile "five"
        o.sensor_tau_s = sim::RigConfig::Defaults().thermal.sensor_tau_s;
        const SensorResult r = Analyze(MakeSimRun(o).run);
        SCOPED_TRACE("seed " + std::to_string(seed) + "\n" + FormatReport(r));
        std::vector<std::string> joint;
        for (const CandidateResult& c : r.candidates)
            if (c.note.find("added jointly with") != std::string::npos) {
                joint.push_back(c.effect);
                EXPECT_NE(c.note.find("to separate: "), std::string::npos) << c.note;
            }
        if (joint.empty()) continue;
        ++joint_runs;
        ASSERT_EQ(joint.size(), 2u);
        for (const std::string& e : joint) EXPECT_TRUE(Added(r, e)) << e;
        EXPECT_NE(r.verdict.find("ambiguous: "), std::string::npos) << r.verdict;
        EXPECT_NE(r.verdict.find("both kept"), std::string::npos) << r.verdict;
        EXPECT_LT(r.residual_all_extended_rms_v, r.residual_all_rms_v);
    }
    std::printf("[ analysis ] collinear pair kept whole on %d of 3 seeds\n", joint_runs);
    EXPECT_GE(joint_runs, 1);
}

// The most runs out of n that a verdict whose thresholds claim a false-positive rate p may flag
// when every one is clean: the smallest k with P(X > k) <= alpha for X ~ Binomial(n, p). A count
// above it says the claimed rate is wrong (at 4.3 % and alpha 0.001 over 40 runs: 7).
int BinomialBound(int n, double p, double alpha) {
    std::vector<double> pmf(static_cast<size_t>(n) + 1);
    for (int k = 0; k <= n; ++k)
        pmf[static_cast<size_t>(k)] =
            std::exp(std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) +
                     k * std::log(p) + (n - k) * std::log1p(-p));
    double above = 1.0;  // P(X > k), k = -1 first
    for (int k = 0; k <= n; ++k) {
        above -= pmf[static_cast<size_t>(k)];
        if (above <= alpha) return k;
    }
    return n;
}

TEST(Discovery, CleanRunsSayNoMissingEffect) {
    // GIVEN 40 clean runs (the rig's effects off)
    // THEN the runs flagged (not "adequate": a candidate named, or a residual left) stay within
    // what the thresholds' claimed false-positive rate allows: the thresholds
    // claim AnalysisOptions::ClaimedFalsePositiveRate() (4.3 % at the defaults) on a run without a
    // missing effect, so the count of flagged runs is Binomial(40, 4.3 %) when the claim holds;
    // asserted: at most the count it exceeds with probability 0.001 (7 of 40). Every run that is
    // adequate must say so.
    const int seeds = 40;
    const AnalysisOptions opts = AnalysisOptions::Defaults();
    const int bound = BinomialBound(seeds, opts.ClaimedFalsePositiveRate(), 1e-3);
    int named = 0, flagged = 0;
    for (int seed = 1; seed <= seeds; ++seed) {
        SimRunOptions o;
        o.seed = 300 + seed;
        const SensorResult r = Analyze(MakeSimRun(o).run, opts);
        if (!r.added.empty()) ++named;
        if (r.outcome != Outcome::kAdequate) {
            ++flagged;
            std::printf("%s", FormatReport(r).c_str());
        } else {
            EXPECT_EQ(r.verdict.rfind("no missing effect: adequate", 0), 0u) << r.verdict;
        }
    }
    std::printf(
        "[ analysis ] clean runs: %d/%d named a candidate, %d/%d not adequate (%.1f %%; claimed "
        "%.1f %%, bound %d)\n",
        named, seeds, flagged, seeds, 100.0 * flagged / seeds,
        100.0 * opts.ClaimedFalsePositiveRate(), bound);
    EXPECT_EQ(bound, 7);        // the figure the comment states, from the defaults
    EXPECT_LE(flagged, bound);  // a run that names a candidate is not adequate: counted here
}

bool Mentions(const std::vector<std::string>& lines, const std::string& what) {
    for (const std::string& l : lines)
        if (l.find(what) != std::string::npos) return true;
    return false;
}

TEST(BadInput, NoRotationsNoSupplyFewPlateaus) {
    SimRunOptions o;
    o.seed = 401;
    o.record_supply = false;
    SimRun s = MakeSimRun(o);
    s.run.sensitivities.clear();
    s.run.plateaus.resize(2);
    const SensorResult r = Analyze(s.run);
    SCOPED_TRACE(FormatReport(r));
    EXPECT_TRUE(Mentions(r.could_not_test, "sf_asymmetry"));
    EXPECT_TRUE(Mentions(r.could_not_test, "no supply voltage recorded"));
    EXPECT_TRUE(std::isfinite(r.error_before.offset_rms_v));   // the bins carry the declared model
    EXPECT_FALSE(std::isfinite(r.error_before.rate_rms_dps));  // no sensitivity: no deg/s
    EXPECT_TRUE(r.added.empty());  // clean data: nothing invented to fill the gaps
    for (const CandidateResult& c : r.candidates) {
        if (c.effect == "supply" || c.effect == "sf_asymmetry") {
            EXPECT_EQ(c.decision, Decision::kNotTested);
        }
    }
}

TEST(BadInput, NoRampsAndOneTemperature) {
    // A run that stays at its start temperature: no ramps, no branches, one plateau.
    SimRunOptions o;
    o.seed = 402;
    o.setpoints_c = {25.0, 25.0};
    sim::SetEffect(o.effects, "temp_rate", 1e-4);  // present but unobservable without ramps
    const SensorResult r = Analyze(MakeSimRun(o).run);
    SCOPED_TRACE(FormatReport(r));
    EXPECT_TRUE(Mentions(r.could_not_test, "temp_rate: no ramps"));
    EXPECT_TRUE(Mentions(r.could_not_test, "hysteresis"));
    EXPECT_TRUE(Mentions(r.could_not_test, "temp_cubic"));
    EXPECT_FALSE(Added(r, "temp_rate"));
}

TEST(BadInput, GapsAndASensorThatNeverSettled) {
    // GIVEN a clean run with 3 stretches of lost samples (5 % each) and no plateau published (the
    // detector never saw the sensor settle)
    SimRunOptions o;
    o.seed = 404;
    SimRun s = MakeSimRun(o, true);
    std::vector<GyroSample> kept;
    const size_t n = s.raw.size();
    for (size_t i = 0; i < n; ++i) {
        const double f = static_cast<double>(i) / n;
        if ((f > 0.20 && f < 0.25) || (f > 0.50 && f < 0.55) || (f > 0.80 && f < 0.85)) continue;
        kept.push_back(s.raw[i]);
    }
    const int64_t lost = static_cast<int64_t>(n - kept.size());
    SensorRun run = BuildSensorRun("S01", kept, s.encoder, {}, s.run.sensitivities);
    const SensorResult r = Analyze(run);
    SCOPED_TRACE(FormatReport(r));
    // THEN it says what is missing (sequence gaps, no power-on record) and invents nothing; the
    // plateaus are not needed: the declared model and the floor come from the still bins
    EXPECT_TRUE(Mentions(r.notes, std::to_string(lost) + " samples missing by sequence number"));
    EXPECT_TRUE(Mentions(r.notes, "no power-on record"));
    EXPECT_EQ(r.n_plateaus, 0);
    EXPECT_TRUE(std::isfinite(r.floor_rate_rms_dps));
    EXPECT_TRUE(std::isfinite(r.error_before.rate_rms_dps));
    EXPECT_TRUE(r.added.empty()) << r.verdict;
}

TEST(Report, JsonFollowsTheSchema) {
    SimRunOptions o;
    o.seed = 403;
    sim::SetEffect(o.effects, "hysteresis", 1e-3);
    const SimRun s = MakeSimRun(o);
    const SensorResult r = Analyze(s.run);
    const nlohmann::json j = ToJson(std::vector<SensorResult>{r});
    ASSERT_EQ(j["sensors"].size(), 1u);
    const auto& js = j["sensors"][0];
    EXPECT_EQ(js["sensor_id"], "S01");
    EXPECT_TRUE(js["verdict"].is_string());
    for (const auto& c : js["candidates"]) {
        EXPECT_TRUE(c.contains("effect") && c.contains("statistic") && c.contains("decision"));
    }
    ASSERT_GE(js["added"].size(), 1u);
    for (const char* k : {"effect", "term", "coefficient", "stderr", "unit"})
        EXPECT_TRUE(js["added"][0].contains(k));
    for (const char* e : {"error_before", "error_after"})
        for (const char* k : {"offset_rms_v", "rate_rms_dps", "drift_dph"})
            EXPECT_TRUE(js[e][k].is_number()) << e << k;
    EXPECT_TRUE(js["floor_rate_rms_dps"].is_number());
    // The extended model is a coefficient set the compensator can take (it validates on build).
    const auto set = ExtendedCoeffSet(r, "run-1", "7", 1);
    ASSERT_TRUE(set.has_value());
    EXPECT_EQ(set->source, "analysis:7");
    EXPECT_NO_THROW(model::Evaluator{set->offset});
    EXPECT_NE(std::find_if(set->offset.term_names.begin(), set->offset.term_names.end(),
                           [](const std::string& t) { return t.rfind("heating(", 0) == 0; }),
              set->offset.term_names.end());
}

}  // namespace
}  // namespace gyrocal::analysis
