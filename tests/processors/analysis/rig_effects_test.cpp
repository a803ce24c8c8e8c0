// The analysis on runs of the project's own rig with its effects OUTSIDE the candidate list
// (aging, compressor, gsens: producers/sim/README.md) and with candidate-shaped effects whose
// shape differs from the candidate's term (a smooth hysteresis, a warm-up with two time
// constants, a warm-up slower than the search grid). The effects are the rig's, switched on with
// sim::SetEffect exactly as `--effect NAME=VALUE` does; the truth only checks the answers.
//
// Sizes, from the noise: the 10 s-bin floor of these runs is ~0.11 mV and the floor bound of the
// outcome (analyze.hpp, step 9) ~0.35 mV; each effect is made 2-10x the bound in RMS over the
// still data, so that a missed one must show as a residual above the bound (a smaller one is, by
// the bound's construction, indistinguishable from the slow noise). The rig's effects are
// exaggerated against an ADXRS610's datasheet for that reason (by how much:
// producers/sim/README.md#what-the-analysis-makes-of-them).
// Four seeds each (noise and unit drawn anew). What is asserted:
//   outside effects: NO candidate is named (none is the cause; the declared model has no lag
//     effect because the sensor lag is 0.1 s), the outcome is "unexplained residual" or "partly
//     explained", and the diagnostic points to the cause: the first generic feature that explains
//     the held-out data is time-shaped for aging, periodic within 15 % of the true period for the
//     compressor (the periodogram's resolution over a ~4700 s run and the noise);
//   candidate-shaped: either the right candidate with a sensible parameter, or an honest
//     "unexplained"/"partly explained"; never another candidate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/report.hpp"
#include "tests/processors/analysis/feature_lookup.hpp"
#include "tests/processors/analysis/sim_run.hpp"

namespace gyrocal::analysis {
namespace {

using testing::FirstExplaining;
using testing::MakeSimRun;
using testing::SimRunOptions;

constexpr int kSeeds = 4;

bool TimeShaped(const FeatureResult& f) {
    return f.channel == "time" || f.channel == "time since power-on";
}

double PeriodOf(const FeatureResult& f) {
    const auto p = f.detail.find("period ");
    return p == std::string::npos ? NAN : std::stod(f.detail.substr(p + 7));
}

std::string AddedNames(const SensorResult& r) {
    std::string s;
    for (const AddedEffect& a : r.added) s += (s.empty() ? "" : ", ") + a.effect + " " + a.term;
    return s.empty() ? "none" : s;
}

// Says that something is left: above the floor (unexplained / partly explained), or two shapes
// the data cannot tell apart (ambiguous, both named with the measurement that would separate
// them).
bool Honest(const SensorResult& r) {
    return r.outcome == Outcome::kUnexplained || r.outcome == Outcome::kPartlyExplained ||
           r.outcome == Outcome::kAmbiguous;
}

// One line per seed, so the figures are in the test log whatever the result.
void Print(const char* name, uint64_t seed, const SensorResult& r) {
    const FeatureResult* f = FirstExplaining(r);
    std::printf(
        "[ rig effect ] %s seed %d: %s; added %s; residual/bound %.2f; first explaining "
        "feature %s %s; residual period %.0f s, trend %.2f mV/h (z %.1f)\n",
        name, static_cast<int>(seed), ToString(r.outcome), AddedNames(r).c_str(), r.excess_ratio,
        f ? f->feature.c_str() : "-", f ? f->detail.c_str() : "", r.residual.period_s,
        r.residual.trend_v_per_h * 1e3, r.residual.trend_z);
}

// An effect outside the list: no candidate, an honest outcome, and the right diagnostic.
// `setpoints` empty: SimRunOptions' (down, up, down, up, down).
void RunOutside(const char* name, const std::vector<std::string>& effects,
                const std::function<bool(const SensorResult&)>& points_to_it,
                const std::vector<double>& setpoints = {}) {
    for (int i = 1; i <= kSeeds; ++i) {
        SimRunOptions o;
        o.seed = 900 + i;
        if (!setpoints.empty()) o.setpoints_c = setpoints;
        for (const std::string& e : effects) sim::ParseEffect(o.effects, e);
        const SensorResult r = Analyze(MakeSimRun(o).run);
        Print(name, o.seed, r);
        SCOPED_TRACE(std::string(name) + " seed " + std::to_string(o.seed) + "\n" +
                     FormatReport(r));
        EXPECT_TRUE(r.added.empty()) << "named a candidate: " << AddedNames(r);
        EXPECT_TRUE(Honest(r)) << ToString(r.outcome);
        EXPECT_TRUE(points_to_it(r)) << "the diagnostic does not point to the cause";
    }
}

TEST(RigOutside, AgingIsTracedToTime) {
    // 2 mV/h: 2.6 mV over the ~4700 s run (RMS ~0.75 mV about its mean, ~2x the bound).
    RunOutside("aging 2 mV/h", {"aging=0.002"}, [](const SensorResult& r) {
        const FeatureResult* f = FirstExplaining(r);
        return f != nullptr && TimeShaped(*f);
    });
}

// The same drift over monotonic setpoints (-40, -10, 25, 55, 85 degC, "five"): time and
// temperature rise together, the declared quadratic absorbs most of the drift, and what is left
// near the start looks like a warm-up with a negative amplitude.
// Before the rule that a warm-up at the upper end of its tau grid gives way to a time-shaped
// feature that predicts its held-out residual at least as well (analyze.cpp, Displace), the
// analysis named warmup(431) here on 3 of 4 seeds ("explained", -1.74 .. -1.86 mV).
TEST(RigOutside, AgingOnMonotonicSetpointsIsNotBlamedOnAWarmup) {
    RunOutside("aging 2 mV/h, monotonic setpoints", {"aging=0.002"},
               [](const SensorResult& r) {
                   const FeatureResult* f = FirstExplaining(r);
                   return f != nullptr && TimeShaped(*f);
               },
               {-40.0, -10.0, 25.0, 55.0, 85.0});
}

TEST(RigOutside, CompressorCycleIsTracedToItsPeriod) {
    // 0.8 mV at a 700 s cycle (RMS 0.57 mV): the periodic feature at the true period.
    RunOutside("compressor 0.8 mV 700 s", {"compressor=0.0008", "compressor_period_s=700"},
               [](const SensorResult& r) {
                   const FeatureResult* f = FirstExplaining(r);
                   return f != nullptr && f->feature == "periodic" &&
                          std::fabs(PeriodOf(*f) / 700.0 - 1.0) < 0.15;
               });
}

// The table's axis tilted 2 deg, 0.1 V/g in the sensor's plane: the null at +90 deg is 3.5 mV
// below the null at 0 deg. The still bins at +90 (the 20 s rests) carry it; and the rotation
// estimate over each move integrates the null's change against rest offsets averaged over 0 and
// +90 deg, which biases the sensitivity with the sign of the move's direction.
// Before the table-angle feature and the rule that an angle-dependent null makes sf_asymmetry
// not attributed (analyze.cpp, AngleConfound), sf_asymmetry was named on 2 of these 4 seeds
// (902: direction term z2 27 against 25). Now the asymmetry is reported as not attributed and the
// first explaining feature is the table angle.
TEST(RigOutside, GsensThroughATiltedTableIsTracedToTheTableAngle) {
    RunOutside("gsens 0.1 V/g tilt 2 deg", {"gsens=0.1", "tilt_deg=2"}, [](const SensorResult& r) {
        const FeatureResult* f = FirstExplaining(r);
        return f != nullptr && f->channel.find("angle") != std::string::npos;
    });
}

// The candidate-shaped effects: `right` names the candidate whose term has the nearest shape;
// `sensible` judges its fitted parameter when it is added. Asserted on every seed: no other
// candidate, never "adequate" (each effect is several times the floor bound), and when the right
// one is named its parameter is sensible; over the seeds: the right one named on at least
// `min_named` (the effect's shape differs from the term's, so a seed may honestly end
// "unexplained" instead; a test that passed with every seed unexplained would test nothing).
void RunShaped(const char* name, const std::vector<std::string>& effects, const char* right,
               const std::function<bool(const AddedEffect&, const CandidateResult&)>& sensible,
               int min_named) {
    int named = 0;
    for (int i = 1; i <= kSeeds; ++i) {
        SimRunOptions o;
        o.seed = 920 + i;
        for (const std::string& e : effects) sim::ParseEffect(o.effects, e);
        const SensorResult r = Analyze(MakeSimRun(o).run);
        Print(name, o.seed, r);
        SCOPED_TRACE(std::string(name) + " seed " + std::to_string(o.seed) + "\n" +
                     FormatReport(r));
        EXPECT_NE(r.outcome, Outcome::kAdequate);
        for (const AddedEffect& a : r.added) {
            EXPECT_EQ(a.effect, right) << "named a wrong candidate: " << a.effect;
            if (a.effect != right) continue;
            ++named;
            const CandidateResult* c = testing::CandidateFor(r, right);
            ASSERT_NE(c, nullptr);
            EXPECT_TRUE(sensible(a, *c)) << a.term << " " << a.coefficient << " +- " << a.stderr_;
        }
        if (r.added.empty()) {
            EXPECT_TRUE(Honest(r)) << "missed, so it must be reported";
        }
    }
    std::printf("[ rig effect ] %s: %s named on %d of %d seeds\n", name, right, named, kSeeds);
    EXPECT_GE(named, min_named);
}

// The parameter in a term's name, e.g. 312 in "warmup(312)".
double TermParam(const std::string& term) {
    const auto open = term.find('(');
    return open == std::string::npos ? NAN : std::stod(term.substr(open + 1));
}

TEST(RigShaped, SmoothHysteresis) {
    // 3 mV between branches reached over a 3 degC travel (e-folding): the analysis' play
    // operator of some width is the nearest shape. Sensible: the branch distance within 40 % of
    // the truth (the play operator's straight ramp and the exponential approach differ most
    // right after a reversal) and a width inside the searched range.
    RunShaped(
        "smooth hysteresis 3 mV travel 3 C", {"hysteresis_smooth=0.003", "hysteresis_travel_c=3"},
        "hysteresis",
        [](const AddedEffect& a, const CandidateResult& c) {
            return std::fabs(std::fabs(a.coefficient) * 2.0 / 0.003 - 1.0) < 0.4 && !c.grid_edge;
        },
        3);
}

TEST(RigShaped, WarmupWithTwoTimeConstants) {
    // 2 mV at 120 s plus 2 mV at 400 s: one exponential cannot be both. Sensible: a time constant
    // between the two (halved and doubled for the noise of the search on a ~4700 s run).
    RunShaped(
        "warm-up 120 s + 400 s",
        {"warmup=0.002", "warmup_tau_s=120", "warmup2=0.002", "warmup2_tau_s=400"}, "warmup",
        [](const AddedEffect& a, const CandidateResult&) {
            const double tau = TermParam(a.term);
            return tau > 60.0 && tau < 800.0;
        },
        3);
}

TEST(RigShaped, WarmupSlowerThanTheSearchGrid) {
    // 4 mV at tau 4000 s: beyond the grid (warmup_tau_max_s 3000 s and a tenth of the still span,
    // ~470 s). A warm-up term may only be added with its time constant flagged at the grid's edge.
    RunShaped(
        "warm-up tau 4000 s", {"warmup=0.004", "warmup_tau_s=4000"}, "warmup",
        [](const AddedEffect&, const CandidateResult& c) { return c.grid_edge; }, 0);
}

}  // namespace
}  // namespace gyrocal::analysis
