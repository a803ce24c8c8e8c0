// The model the analysis finds survives the trip to the compensators: on the project's simulated
// rig with one undeclared effect switched on (temp_rate, hysteresis, warmup, supply,
// sf_asymmetry, temp_cubic), several seeds, the rig's default temperature-sensor lag (15 s) and
// the `five` profile's setpoints (-40, -10, 25, 55, 85 degC from a 25 degC start), the extended
// coefficient set `gyrocal analyze` would store is applied by the live compensator's library to a
// held-out RAMP run of the same units (same unit seed, another noise seed; the chamber ramps
// -10 -> 70 -> 10 -> 50 degC at the calibration's ramp rate with the table at rest, so every
// dynamic input - dT/dt, branch, time since power-on - moves as it would in use). Its error (rate
// RMS over 10 s bins) is compared with what the rig's true model leaves on the same samples (the
// truth, effects included, evaluated at the MEASURED temperature: the best any model of the
// measured temperature can do; virtual_lab::EvaluateHeldOut's floor_meas).
//
// The bound, from the noise: both figures share the samples, so the white and slow noise of the
// ramp run cancel from the comparison except through the extended model's own coefficient error,
// which comes from the CALIBRATION run's noise. A fitted model's prediction error over the ramp
// bins (its covariance propagated to each bin, RMS over bins: PredictionRms below) adds in
// quadrature: after^2 = truth^2 + prediction^2 when the model is right. The coefficient error is
// one shape over the whole record (one degree of freedom), so 3 sigma of it is 3x the RMS:
//   after <= sqrt(truth^2 + 9 prediction^2).
// The covariance is the analysis' autocorrelation-robust one, estimated from the fit's residuals,
// so a model that misses a term gets a wider bound: the bound catches a broken model path (a
// term evaluated with other inputs than it was fitted on: the 9x), not a missed term.
// Asserted for every case, unless the analysis itself said something is left (unexplained,
// partly explained) or ties (ambiguous). And on every seed, against the truth: no candidate is
// added that the truth lacks (temp_rate and thermometer_lag are in the truth: the 15 s
// thermometer lag on the rig's curved offset), and the
// switched-on effect is named - added, or named in a tie the verdict states - whenever the part of
// it the analysis can see (its offset in the still bins less the declared quadratic:
// VisibleEffectRms) is above the floor bound the analysis measured on the run (white scatter and
// the run's own slow noise: analyze.hpp step 9), the size below which its verdict claims nothing.
// On these seeds the effects are 2.6-3.7x the 10 s-bin floor but, except temp_cubic, 0.3-0.6x
// the floor bound (the slow noise of this profile with a 15 s thermometer lag); the figures are
// printed per seed.
//
// The acceptance figure, after <= 1.2 truth: the true model's error on these samples is itself
// noise (white and slow gyro noise in 10 s bins, the thermometer's lag and noise: nothing a model
// of the measured temperature can remove), so the bound is 1.2x the noise on the same samples; it
// leaves the extended model sqrt(1.2^2 - 1) = 0.66x that noise for its own coefficient error (the
// prediction above is 0.1-0.4x of it in every case below) and for what it still lacks. Asserted
// for every case except the listed misses (kMisses), which the analysis cannot bring within it
// on this profile, each for a stated reason (and the table of
// processors/analysis/README.md#held-out-ramp-encompassing-test-the-cases-above-12x); for them
// only the assertion above holds (within the noise bound, or the analysis said it left something
// unexplained). A listed miss that comes within 1.2x is printed, so that the list can shrink.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/report.hpp"
#include "processors/model/model.hpp"
#include "tests/processors/analysis/sim_run.hpp"
#include "tests/support/virtual_lab/held_out.hpp"

namespace gyrocal::analysis {
namespace {

using testing::MakeSimRun;
using testing::SimRun;
using testing::SimRunOptions;

double Rms(const std::vector<double>& v) {
    double ss = 0;
    int n = 0;
    for (double x : v)
        if (std::isfinite(x)) {
            ss += x * x;
            ++n;
        }
    return n ? std::sqrt(ss / n) : NAN;
}

// [deg/s] RMS over the record's bins of the offset model's prediction standard deviation
// (sqrt(j' C j) at the bin's steady-state inputs) over the nominal sensitivity: the part of the
// error that comes from the calibration's noise through the fitted coefficients.
double PredictionRms(const model::CoeffSet& set, const virtual_lab::SensorHeldOut& s) {
    const model::Evaluator off(set.offset), sens(set.sensitivity);
    double ss = 0;
    int n = 0;
    for (double t : s.temp_c) {
        const model::ModelInputs in = model::SteadyStateInputs(set.offset, t);
        const double sd = std::sqrt(off.Evaluate(in, model::RangePolicy::kClip).variance);
        const double sv =
            sens.Value(model::SteadyStateInputs(set.sensitivity, t), model::RangePolicy::kClip);
        if (!std::isfinite(sd) || !std::isfinite(sv)) continue;
        ss += (sd / sv) * (sd / sv);
        ++n;
    }
    return n ? std::sqrt(ss / n) : NAN;
}

// [V] RMS over the still bins of the switched-on effect's offset (the rig's truth per sample,
// averaged in the analysis' bins) after projecting out the declared quadratic in the measured
// temperature: the part of it the analysis can possibly see.
double VisibleEffectRms(const SimRun& s) {
    const BinnedRun b(s.run, BinOptions::Defaults());
    const auto n = static_cast<Eigen::Index>(b.size());
    Eigen::VectorXd v(n);
    Eigen::MatrixXd x(n, 3);
    size_t k = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
        const Bin& bin = b.bins()[static_cast<size_t>(i)];
        double sum = 0.0;
        int m = 0;
        while (k < s.run.samples.size() && s.run.samples[k].utime < bin.start_utime) ++k;
        for (size_t j = k; j < s.run.samples.size() && s.run.samples[j].utime < bin.end_utime; ++j)
            sum += s.effect_offset_v[j], ++m;
        v[i] = m > 0 ? sum / m : 0.0;
        const double dt = bin.temp_c - 25.0;
        x.row(i) << 1.0, dt, dt * dt;
    }
    const Eigen::VectorXd r = v - x * x.colPivHouseholderQr().solve(v);
    return n > 0 ? std::sqrt(r.squaredNorm() / static_cast<double>(n)) : NAN;
}

struct Outcome {
    double after = NAN, truth = NAN, prediction = NAN;
    std::string added;
    std::string report;              // the analysis' report, for a failure's message
    bool flagged = false;            // the analysis said something is left (or two shapes tie)
    bool named = false;              // the switched-on effect is among the added terms
    bool named_in_tie = false;       // or named in an ambiguity (the data could not tell it apart)
    std::vector<std::string> wrong;  // added terms the truth does not have
    double size_over_bound = NAN;    // VisibleEffectRms over the analysis' floor bound
    double size_over_floor = NAN;    // and over its floor (10 s-bin scatter)
};

Outcome OneSeed(const char* effect, double value, uint64_t seed, bool lag_candidate) {
    SimRunOptions o;
    o.seed = seed;
    sim::SetEffect(o.effects, effect, value);
    o.setpoints_c = {-40.0, -10.0, 25.0, 55.0, 85.0};  // sequencer profile "five"
    o.sensor_tau_s = sim::RigConfig::Defaults().thermal.sensor_tau_s;
    const SimRun s = MakeSimRun(o);
    AnalysisOptions ao = AnalysisOptions::Defaults();
    ao.thermometer_lag_candidate = lag_candidate;
    const SensorResult r = Analyze(s.run, ao);
    Outcome out;
    out.report = FormatReport(r);
    out.size_over_bound = VisibleEffectRms(s) / r.floor_bound_rms_v;
    out.size_over_floor = VisibleEffectRms(s) / r.floor_offset_rms_v;
    out.flagged = r.outcome == analysis::Outcome::kUnexplained ||
                  r.outcome == analysis::Outcome::kPartlyExplained ||
                  r.outcome == analysis::Outcome::kAmbiguous;
    for (const AddedEffect& a : r.added) {
        out.added += (out.added.empty() ? "" : ",") + a.effect;
        out.named = out.named || a.effect == effect;
        // The rig's 15 s thermometer lag is itself a temp_rate effect, and on its curved offset a
        // thermometer_lag one (dT x dT/dt, 2 o2 x 15 s): the truth has both.
        if (a.effect != effect && a.effect != "temp_rate" && a.effect != "thermometer_lag")
            out.wrong.push_back(a.effect);
    }
    for (const std::string& a : r.ambiguities)
        out.named_in_tie = out.named_in_tie || a.find(effect) != std::string::npos;
    const auto ext = ExtendedCoeffSet(r, "calibration", "1", 1);
    if (!ext) {
        ADD_FAILURE() << effect << " seed " << seed << ": no extended set\n" << FormatReport(r);
        return out;
    }
    sim::RigConfig ramp = s.config;
    ramp.noise_seed = seed + 1000;  // same units, fresh noise
    virtual_lab::HeldOutProfile p;
    p.waypoints_c = {-10.0, 70.0, 10.0, 50.0};
    p.ramp_c_per_min = o.ramp_c_per_min;
    p.hold_s = 600.0;
    p.bin_s = 10.0;
    const virtual_lab::HeldOutResult h =
        virtual_lab::EvaluateHeldOut(ramp, p, {{{ext->sensor_id, *ext}}});
    const virtual_lab::SensorHeldOut& u = h.sensors.at(0);
    EXPECT_EQ(u.not_compensated.at(0), 0)
        << effect << " seed " << seed << ": every sample is computable";
    out.after = Rms(u.err_dps.at(0));
    out.truth = Rms(u.floor_meas_dps);
    out.prediction = PredictionRms(*ext, u);
    return out;
}

// The cases still above 1.2x the true model, and why (measured on this profile and these seeds;
// the figures: processors/analysis/README.md#held-out-ramp-encompassing-test-the-cases-above-12x):
//   hysteresis 202: hysteresis added and confirmed, just above 1.2x. Two causes, neither one a
//                   term the analysis could honestly choose: (1) `five` reverses the temperature
//                   once, so the training bins do not resolve the branch width (their residual
//                   is flat over widths of 2-8 degC; the one chosen is at the wide end), while
//                   the ramp run reverses three times; (2) what is left follows dT/dt with a
//                   coefficient that changes with temperature (the thermometer's lag times the
//                   offset's slope), a shape no candidate has (dTdt(tau) has one coefficient,
//                   not significant on this run);
//   warmup 202:     the warm-up is found on the training bins (z2 far above the threshold), but
//                   the held-out blocks hold the run's only data below the training bins' coldest
//                   temperature (the -40 degC setpoint) and the end of the warm-up, so the gate
//                   judges the quadratic's extrapolation there more than the term: fitted with
//                   the term, the training bins' polynomial lands further from the truth at
//                   -43 degC than without it, and the gate refuses the term ("not confirmed on
//                   the held-out data: warmup"; within the noise bound of the declared model's
//                   own covariance). Holding each block out in turn (each rotation choosing its
//                   own terms) does not confirm it either: the rotation that holds out the first
//                   block cannot see the warm-up and chooses nothing.
const std::set<std::pair<std::string, uint64_t>> kMisses = {{"hysteresis", 202}, {"warmup", 202}};

void RunEffect(const char* effect, double value, bool lag_candidate = false) {
    constexpr int kSeeds = 3;
    int within = 0;
    for (int k = 1; k <= kSeeds; ++k) {
        const uint64_t seed = 200 + k;
        const Outcome o = OneSeed(effect, value, seed, lag_candidate);
        const double noise_bound = std::sqrt(o.truth * o.truth + 9 * o.prediction * o.prediction);
        std::printf(
            "[ held-out ] %-12s seed %llu: extended %.4f deg/s, true model %.4f deg/s "
            "(x%.2f), prediction %.4f, noise bound %.4f; added %s; effect %.2fx the floor "
            "bound, %.2fx the floor\n",
            effect, static_cast<unsigned long long>(seed), o.after, o.truth, o.after / o.truth,
            o.prediction, noise_bound, o.added.empty() ? "nothing" : o.added.c_str(),
            o.size_over_bound, o.size_over_floor);
        const bool listed = kMisses.count({effect, seed}) > 0;
        if (o.after <= 1.2 * o.truth) {
            ++within;
            if (listed)
                std::printf("[ held-out ] %s seed %llu is listed as a miss but is within 1.2x\n",
                            effect, static_cast<unsigned long long>(seed));
        } else {
            std::printf("[ held-out ] above 1.2x the true model; the analysis said:\n%s",
                        o.report.c_str());
        }
        // The effect is named, alone or in a tie the verdict states, when it is above the floor
        // bound; no candidate the truth lacks.
        if (o.size_over_bound > 1.0) {
            EXPECT_TRUE(o.named || o.named_in_tie) << effect << " seed " << seed << "\n"
                                                   << o.report;
        }
        EXPECT_TRUE(o.wrong.empty()) << effect << " seed " << seed << ": named " << o.added;
        // Within the noise of the true model whenever the analysis claims the model is complete;
        // beyond it only when the verdict says something is left or ties.
        EXPECT_TRUE(o.after <= noise_bound || o.flagged)
            << effect << " seed " << seed << ": extended " << o.after
            << " deg/s above the noise bound " << noise_bound
            << " and the analysis did not say so\n"
            << o.report;
        if (!listed) {
            EXPECT_LE(o.after, 1.2 * o.truth)
                << effect << " seed " << seed << ": extended " << o.after << " deg/s, true model "
                << o.truth << " deg/s\n"
                << o.report;
        }
    }
    std::printf("[ held-out ] %-12s within 1.2x of the true model on %d of %d seeds\n", effect,
                within, kSeeds);
}

TEST(HeldOutRamp, TempRate) { RunEffect("temp_rate", 1e-4); }
// With the thermometer_lag candidate searched (off by default): on seed 202 temp_rate and
// hysteresis (projected correlation 0.94) entered as a pair whose split was determined against the
// full model's noise, then thermometer_lag entered and took what had told them apart (hysteresis
// z2 3.46 with the rest in, below min_pair_member_z2 4); a pair member is re-tested against the
// criterion it entered under (selection.cpp RemoveWeakTerms), so hysteresis is not attributed.
TEST(HeldOutRamp, TempRateWithLagCandidate) { RunEffect("temp_rate", 1e-4, true); }
TEST(HeldOutRamp, Hysteresis) { RunEffect("hysteresis", 1e-3); }
TEST(HeldOutRamp, Warmup) { RunEffect("warmup", 2e-3); }
TEST(HeldOutRamp, Supply) { RunEffect("supply", 0.05); }
TEST(HeldOutRamp, SfAsymmetry) { RunEffect("sf_asymmetry", 0.02); }
TEST(HeldOutRamp, TempCubic) { RunEffect("temp_cubic", 2e-8); }

}  // namespace
}  // namespace gyrocal::analysis
