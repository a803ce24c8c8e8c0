// The windows test (evidence.hpp, WindowsAbove) keeps its false-positive rate when the noise
// level the surrogates are drawn with is not the data's. In an analysis that level is the run's
// own, estimated from the run with tens of % error
// (processors/analysis/README.md#thresholds-from-the-run-itself, its windows item): a run whose
// level was underestimated meets surrogates too quiet. Here null data (noise only, the declared
// quadratic fitted) are drawn with a known model and the surrogates with the same model at 0.7x
// or 1.4x its level (Allan deviation; within the spread of the estimate on the rig's clean runs,
// where the fitted Allan variance at 1200 s over the truth spans 0.28..3.27). The studentised
// statistic divides each window's |mean| by the Allan deviation of the terms refitted on the same
// vector, run and surrogates alike, so the level cancels and the share flagged is the one the right
// level gives; the plug-in |mean| alone is not (the second test: 45.7 % flagged at 0.7x, 0.7 %
// at 1.4x, 8.0 % at the right level). A surrogate model whose shape is off too (flicker B alone
// 0.7x or 1.4x, white noise right) gave 9.0 % and 10.0 % of the same 300 runs, against 9.3 % with
// the surrogates right (2026-11-29, once, not a test: within the noise). Why 9.3 % and not 4.95 %:
// see CheckLevel below.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins.hpp"
#include "processors/analysis/evidence.hpp"
#include "processors/analysis/noise_model.hpp"
#include "processors/analysis/run_data.hpp"

namespace gyrocal::analysis::detail {
namespace {

constexpr double kUs = 1e6;
constexpr double kBinS = 10.0;
constexpr double kArw =
    3e-4;  // [V/sqrt(Hz)] N, near the rig's
           // (processors/analysis/README.md#thresholds-from-the-run-itself: 0.295 mV/rtHz)
constexpr double kFlicker = 5e-5;  // [V] B, near the rig's (0.047 mV)

// A run as long as the rig's (4780 s: two 2400 s tiles) with one turn: 2 still stretches of 239
// bins of 10 s, 20 s apart, the temperature a full sine between -10 and 70 degC (every band
// visited). Two stretches, not the rig's dozen: with fewer than 3 there is no screening and no
// jackknife in the refit (noise::FitTerms), which makes the 60000 refits below affordable.
std::vector<Bin> RigLikeBins() {
    std::vector<Bin> bins;
    double t_s = 0.0;
    for (int s = 0; s < 2; ++s, t_s += 20.0)
        for (int k = 0; k < 239; ++k, t_s += kBinS) {
            Bin b;
            b.mid_utime = (t_s + 0.5 * kBinS) * kUs;
            b.n = 1000;
            b.segment = s;
            b.temp_c = 30.0 + 40.0 * std::sin(2.0 * M_PI * t_s / 4780.0);
            bins.push_back(b);
        }
    return bins;
}

// Share of null runs the windows test flags, with surrogates whose Allan deviation is `level` x
// the data's (white and flicker alike).
double FlaggedShare(WindowStatistic statistic, double level, int trials, uint64_t seed) {
    const std::vector<Bin> layout = RigLikeBins();
    NoiseModel truth;
    truth.white_v2 = kArw * kArw / kBinS;
    truth.flicker_v = kFlicker;
    NoiseModel off = truth;
    off.white_v2 = level * level * truth.white_v2;
    off.flicker_v = level * kFlicker;
    const SurrogateNoise data(truth, layout, kBinS), surrogate(off, layout, kBinS);
    // The declared quadratic in temperature, fitted on all bins as the final model's design.
    Eigen::MatrixXd x(static_cast<Eigen::Index>(layout.size()), 3);
    for (size_t i = 0; i < layout.size(); ++i) {
        const double dt = layout[i].temp_c - 25.0;
        x.row(static_cast<Eigen::Index>(i)) << 1.0, dt, dt * dt;
    }
    AnalysisOptions o;
    o.window_statistic = statistic;
    o.surrogates = 100;
    o.window_fpr = 0.05;
    const SensorRun run;
    std::mt19937_64 rng(seed);
    int flagged = 0;
    for (int t = 0; t < trials; ++t) {
        std::vector<Bin> bins = layout;
        const Eigen::VectorXd y = data.Draw(rng);
        for (size_t i = 0; i < bins.size(); ++i) bins[i].gyro_v = y[static_cast<Eigen::Index>(i)];
        const BinnedRun b(run, kBinS, std::move(bins), nullptr);
        Surrogates s;
        s.model = off;
        for (int k = 0; k < o.surrogates; ++k) s.noise.push_back(surrogate.Draw(rng));
        flagged += !WindowsAbove(b, x, s, o, nullptr).empty();
    }
    return static_cast<double>(flagged) / trials;
}

// The windows test at the surrogates' right level and at 0.7x and 1.4x of it, on the same null
// runs: with the studentised statistic the level cancels, so the share flagged is the one the
// right level gives; the tolerance is 3 binomial standard errors of a difference of two shares
// over 300 runs each (taken as independent: they are not, the same runs are judged, so this is
// generous to a statistic that does depend on the level - the plug-in still fails it, below).
// The share at the right level is NOT window_fpr's 5/101 = 4.95 %: MaxTNull standardises each
// surrogate's windows by moments that include that surrogate, which shrinks the surrogates' own
// largest values and not the run's; with these 22 windows, 100 surrogates and 5 % it flags 7.9 %
// of exchangeable half-normal statistics (1.50 % with the analysis' 200 surrogates at 1 %), a
// separate matter (processors/analysis/README.md#thresholds-from-the-run-itself). 5 % and 100
// surrogates: the 90000 refits stay affordable.
struct LevelCheck {
    double right = 0.0, se = 0.0;   // share flagged at the right level, the tolerance's unit
    double shares[2] = {0.0, 0.0};  // at 0.7x and 1.4x
    bool Holds(int k) const { return std::fabs(shares[k] - right) <= 3.0 * se; }
};
constexpr double kRatios[2] = {0.7, 1.4};

LevelCheck CheckLevel(WindowStatistic statistic, int trials) {
    LevelCheck c;
    c.right = FlaggedShare(statistic, 1.0, trials, 5);
    c.se = std::sqrt(2.0 * c.right * (1.0 - c.right) / trials);
    for (int k = 0; k < 2; ++k) c.shares[k] = FlaggedShare(statistic, kRatios[k], trials, 5);
    return c;
}

TEST(WindowsNoiseLevel, StudentisedWindowsKeepTheirRateWhenTheSurrogatesLevelIsOff) {
    const LevelCheck c = CheckLevel(WindowStatistic::kStudentised, 300);
    for (int k = 0; k < 2; ++k)
        EXPECT_TRUE(c.Holds(k)) << "surrogates' level x " << kRatios[k] << ": " << c.shares[k]
                                << " flagged, " << c.right << " at the right level, se " << c.se;
    std::printf(
        "studentised: %.4f flagged at the right level, %.4f at 0.7x, %.4f at 1.4x (se %.4f)\n",
        c.right, c.shares[0], c.shares[1], c.se);
}

// The same check with the plug-in statistic fails (measured 2026-11-29: see the message): the
// test can fail.
TEST(WindowsNoiseLevel, PluginWindowsFailTheSameCheck) {
    const LevelCheck c = CheckLevel(WindowStatistic::kPlugin, 300);
    EXPECT_FALSE(c.Holds(0) && c.Holds(1))
        << c.right << " at the right level, " << c.shares[0] << " at 0.7x, " << c.shares[1]
        << " at 1.4x, se " << c.se;
    std::printf("plug-in: %.4f flagged at the right level, %.4f at 0.7x, %.4f at 1.4x (se %.4f)\n",
                c.right, c.shares[0], c.shares[1], c.se);
}

}  // namespace
}  // namespace gyrocal::analysis::detail
