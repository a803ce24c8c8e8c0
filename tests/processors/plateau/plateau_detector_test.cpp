// PlateauDetector on synthetic temperature traces with known truth. Noise: temperature white
// sigma_T = 0.05 degC, gyro 2 mV rms, 100 Hz. Every tolerance below is derived from these.
#include "processors/plateau/plateau_detector.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "tests/processors/plateau/synthetic_temperature.hpp"
#include "tests/processors/validate_check.hpp"

namespace gyrocal::plateau {
namespace {

using testing::FirstOrderLag;
using testing::Stream;
using testing::StreamSpec;

struct RunResult {
    std::vector<Plateau> plateaus;
    std::vector<StateReport> reports;
};

// Feeds n_s seconds of the stream; `hook(t_s)` runs before each sample (setpoint changes ...);
// `moving(t_s)` flags table motion.
template <class Hook, class Moving>
RunResult Feed(PlateauDetector& det, Stream& stream, double n_s, Hook hook, Moving moving,
               double moving_temp_offset_c = 0, double moving_gyro_offset_v = 0) {
    RunResult r;
    const int64_t n = static_cast<int64_t>(n_s * testing::kRateHz);
    for (int64_t k = 0; k < n; ++k) {
        Sample s = stream.Next();
        const double t = Stream::TimeOf(s.utime);
        hook(t);
        s.moving = moving(t);
        if (s.moving) {
            s.temp_c += moving_temp_offset_c;
            s.gyro_v += moving_gyro_offset_v;
        }
        Step st = det.Feed(s);
        if (st.plateau) r.plateaus.push_back(*st.plateau);
        if (st.state) r.reports.push_back(*st.state);
    }
    return r;
}

auto NoHook = [](double) {};
auto Still = [](double) { return false; };

// A hook that orders the chamber to `setpoint_c` once, at the first sample at or after `t_s`.
auto SetpointAt(PlateauDetector& det, double t_s, double setpoint_c) {
    return [&det, t_s, setpoint_c, done = false](double t) mutable {
        if (done || t < t_s) return;
        det.SetChamberSetpoint(setpoint_c);
        done = true;
    };
}

// Standard error of a window slope [degC/min] for white scatter sigma over W seconds at 100 Hz:
// sigma * sqrt(12) / (W * sqrt(n)), n = W * 100.
double SlopeSePerMin(double sigma_c, double window_s) {
    return sigma_c * std::sqrt(12.0) / (window_s * std::sqrt(window_s * testing::kRateHz)) * 60.0;
}

TEST(PlateauDetector, FiresOnlyAfterFirstOrderLagHasSettled) {
    // GIVEN a sensor at 25 degC, the chamber ordered to 60 degC at t = 300 s, and the sensor
    // following with a first-order lag tau = 300 s.
    const double tau_s = 300, t_step_s = 300, final_c = 60;
    StreamSpec spec;
    spec.temp_true_c = [&](double t) { return FirstOrderLag(t, t_step_s, 25, final_c, tau_s); };
    Stream stream(spec);
    const PlateauConfig cfg = PlateauConfig::Defaults();
    PlateauDetector det(cfg);
    det.SetChamberSetpoint(25);
    // WHEN 11 tau of data are fed
    RunResult r =
        Feed(det, stream, t_step_s + 11 * tau_s, SetpointAt(det, t_step_s, final_c), Still);
    // THEN one plateau at 25 before the step, and exactly one at 60 after it
    std::vector<Plateau> after;
    for (const Plateau& p : r.plateaus) {
        if (Stream::TimeOf(p.start_utime) >= t_step_s)
            after.push_back(p);
        else
            EXPECT_EQ(p.setpoint_c, 25);
    }
    ASSERT_EQ(after.size(), 1u);
    const Plateau& p = after[0];
    EXPECT_EQ(p.setpoint_c, final_c);
    // The criterion is on a window slope; for the exponential the slope at the end of the
    // window is below the window's slope, so at the start of averaging the true slope is at
    // most the threshold plus 3 standard errors of the slope estimate; the remaining distance to
    // the final temperature is tau * slope.
    const double slope_bound_c_per_s =
        (cfg.slope_max_c_per_min + 3 * SlopeSePerMin(spec.temp_noise_c, cfg.window_s)) / 60.0;
    const double t_start = Stream::TimeOf(p.start_utime);
    EXPECT_LE(std::fabs(spec.temp_true_c(t_start) - final_c), tau_s * slope_bound_c_per_s)
        << "averaging began at t = " << t_start << " s, before the sensor had settled";
    // And not needlessly late: once the true slope at the window's centre is half the
    // threshold (>> 3 SE below it), the criterion holds, so averaging starts within
    // W/2 + min_stable_s (+1 s of sampling slack) of that time.
    const double t_half = t_step_s + tau_s * std::log((final_c - 25) / tau_s * 60.0 /
                                                      (0.5 * cfg.slope_max_c_per_min));
    EXPECT_LE(t_start, t_half + cfg.window_s / 2 + cfg.min_stable_s + 1.0);
    // The plateau's own slope is within the criterion.
    EXPECT_LE(std::fabs(p.temp_slope_c_per_min), cfg.slope_max_c_per_min * cfg.leave_factor);
}

TEST(PlateauDetector, FiresOnlyAfterTheDieHasSettledBehindARampingChamber) {
    // GIVEN the simulated rig's thermal chain: chamber air ramping at 3 degC/min from 25 to
    // 60 degC (air lag 30 s), the die lagging the air (package tau 200 s) and the temperature
    // sensor lagging the die (15 s). Only the sensor is measured.
    const double tau_air = 30, tau_die = 200, tau_sensor = 15, t_order = 300, final_c = 60;
    const double dt = 1.0 / testing::kRateHz;
    struct Thermal {
        double air = 25, die = 25, sensor = 25;
    };
    auto thermal = std::make_shared<Thermal>();
    std::map<int64_t, double> die_at;  // truth of the die by sample time [ms]
    StreamSpec spec;
    spec.temp_true_c = [&, thermal](double t) {
        const double ref = t < t_order ? 25 : std::min(final_c, 25 + 3.0 * (t - t_order) / 60.0);
        Thermal& th = *thermal;
        th.air += (ref - th.air) * (1 - std::exp(-dt / tau_air));
        th.die += (th.air - th.die) * (1 - std::exp(-dt / tau_die));
        th.sensor += (th.die - th.sensor) * (1 - std::exp(-dt / tau_sensor));
        die_at[std::llround(t * 1000)] = th.die;
        return th.sensor;
    };
    Stream stream(spec);
    const PlateauConfig cfg = PlateauConfig::Defaults();
    PlateauDetector det(cfg);
    det.SetChamberSetpoint(25);
    RunResult r = Feed(det, stream, 4000, SetpointAt(det, t_order, final_c), Still);
    std::vector<Plateau> after;
    for (const Plateau& p : r.plateaus)
        if (p.setpoint_c == final_c) after.push_back(p);
    ASSERT_EQ(after.size(), 1u);
    // THEN at the start of averaging the DIE is settled: with the air at its setpoint the die's
    // distance to it is tau_die * |die slope|, and the die's slope is below the sensor's (the
    // sensor shows the die's slope 15 s late, when it was larger), which the criterion bounds
    // by the threshold + 3 SE: 200 s * 0.0536/60 degC/s = 0.18 degC.
    const double t_start = Stream::TimeOf(after[0].start_utime);
    const double die = die_at.at(std::llround(t_start * 1000));
    const double bound =
        tau_die * (cfg.slope_max_c_per_min + 3 * SlopeSePerMin(spec.temp_noise_c, cfg.window_s)) /
        60.0;
    EXPECT_LE(std::fabs(die - final_c), bound) << "averaging began at t = " << t_start << " s";
    EXPECT_NEAR(after[0].temp_c.mean, final_c, bound);
}

TEST(PlateauDetector, NeverFiresDuringARamp) {
    // GIVEN ramps at 2x and 10x the slope threshold, with the temperature scatter near the
    // scatter limit (0.15 degC): the slope estimate's SE is 0.0036 degC/min, so 2x the
    // threshold (0.1) is > 10 SE above it: no window may pass.
    for (double ramp_c_per_min : {0.1, -0.1, 0.5}) {
        StreamSpec spec;
        spec.temp_noise_c = 0.15;
        spec.temp_true_c = [&](double t) { return 20 + ramp_c_per_min * t / 60.0; };
        spec.seed = 11;
        Stream stream(spec);
        PlateauDetector det(PlateauConfig::Defaults());
        RunResult r = Feed(det, stream, 3600, NoHook, Still);
        EXPECT_TRUE(r.plateaus.empty()) << "plateau on a ramp of " << ramp_c_per_min << " degC/min";
        for (const StateReport& s : r.reports) EXPECT_NE(s.state, State::kAveraging);
    }
}

TEST(PlateauDetector, RotationNeitherBreaksStabilityNorIsAveraged) {
    // GIVEN a flat 30 degC trace; during table motion the samples carry a large gyro output
    // (the rotation) and a disturbed temperature, both of which would show if used.
    StreamSpec spec;
    spec.temp_true_c = [](double) { return 30.0; };
    spec.seed = 5;
    auto run = [&](auto moving) {
        Stream stream(spec);
        PlateauDetector det(PlateauConfig::Defaults());
        return Feed(det, stream, 260, NoHook, moving, /*temp*/ 3.0, /*gyro*/ 0.5);
    };
    const RunResult still = run(Still);
    // Motion once while settling (95-100 s) and twice while averaging (130-135, 150-155 s).
    auto in = [](double t, double a, double b) { return t >= a && t < b; };
    const RunResult moved =
        run([&](double t) { return in(t, 95, 100) || in(t, 130, 135) || in(t, 150, 155); });
    ASSERT_EQ(still.plateaus.size(), 1u);
    ASSERT_EQ(moved.plateaus.size(), 1u);
    const Plateau& p = moved.plateaus[0];
    // THEN stability was not reset by the motion: averaging began at the same sample
    EXPECT_EQ(p.start_utime, still.plateaus[0].start_utime);
    // the 10 s of motion inside the averaging window were excluded (1000 samples at 100 Hz)
    EXPECT_EQ(p.n_excluded_motion, 1000);
    // Still time is summed between consecutive still samples, so each motion segment costs one
    // sampling interval: two segments, two more samples than without motion.
    EXPECT_EQ(p.n_samples, still.plateaus[0].n_samples + 2);
    // and the means are those of the still data: within 4 SE (sigma/sqrt(n), white noise) of the
    // truth, while including the motion would shift the gyro mean by 0.5 V * 1000/7000 = 71 mV.
    const double n = p.n_samples;
    EXPECT_NEAR(p.gyro_v.mean, Stream(spec).GyroTruth(30.0), 4 * spec.gyro_noise_v / std::sqrt(n));
    EXPECT_NEAR(p.temp_c.mean, 30.0, 4 * spec.temp_noise_c / std::sqrt(n));
}

// What 300 s of a flat 40 degC trace with white noise (seed 3) in run "run-7" gives the
// default detector, the samples for which `lost(seq)` holds dropped on the way.
struct FlatRun {
    StreamSpec spec;
    std::vector<Plateau> plateaus;
    std::vector<std::string> refused;
};
template <class Lost>
FlatRun FeedFlat40(Lost lost) {
    FlatRun r;
    r.spec.temp_true_c = [](double) { return 40.0; };
    r.spec.seed = 3;
    Stream stream(r.spec);
    PlateauDetector det(PlateauConfig::Defaults());
    det.StartRun("run-7");
    det.SetChamberSetpoint(40);
    for (int64_t k = 0; k < static_cast<int64_t>(300 * testing::kRateHz); ++k) {  // 300 s
        Sample s = stream.Next();
        if (lost(s.seq)) continue;
        Step st = det.Feed(s);
        if (st.plateau) r.plateaus.push_back(*st.plateau);
        if (st.refused) r.refused.push_back(*st.refused);
    }
    return r;
}

TEST(PlateauDetector, PlateauStatisticsMatchTheTruth) {
    // GIVEN a flat 40 degC trace with white noise
    const FlatRun run = FeedFlat40([](int64_t) { return false; });
    const StreamSpec& spec = run.spec;
    const Stream stream(spec);
    const PlateauConfig cfg = PlateauConfig::Defaults();
    const std::vector<Plateau>& got = run.plateaus;
    ASSERT_EQ(got.size(), 1u);
    const Plateau& p = got[0];
    EXPECT_EQ(p.run_id, "run-7");
    EXPECT_EQ(p.setpoint_c, 40);
    EXPECT_EQ(p.plateau_id, p.start_utime);
    EXPECT_EQ(p.seq_gaps, 0);
    EXPECT_EQ(p.n_excluded_motion, 0);
    EXPECT_EQ(p.last_seq - p.first_seq + 1, p.n_samples);
    // 60 s of still time at 100 Hz: 6001 samples spanning 60 s
    EXPECT_NEAR((p.end_utime - p.start_utime) * 1e-6, cfg.average_s, 0.011);
    EXPECT_EQ(p.n_samples, 6001);
    const double n = p.n_samples;
    // Means within 4 sigma/sqrt(n); sample std within 4 of its standard error sigma/sqrt(2n).
    EXPECT_NEAR(p.temp_c.mean, 40.0, 4 * spec.temp_noise_c / std::sqrt(n));
    EXPECT_NEAR(p.gyro_v.mean, stream.GyroTruth(40.0), 4 * spec.gyro_noise_v / std::sqrt(n));
    EXPECT_NEAR(p.temp_c.std, spec.temp_noise_c, 4 * spec.temp_noise_c / std::sqrt(2 * n));
    EXPECT_NEAR(p.gyro_v.std, spec.gyro_noise_v, 4 * spec.gyro_noise_v / std::sqrt(2 * n));
    // Batch-means SEM of white noise: sigma/sqrt(n), estimated with relative scatter
    // 1/sqrt(2 (B - 2)) = 0.167 for B = 20; allow 3 of those.
    const double rel = 3 / std::sqrt(2.0 * (cfg.sem_batches - 2));
    EXPECT_NEAR(p.gyro_v.sem / (spec.gyro_noise_v / std::sqrt(n)), 1.0, rel);
    EXPECT_NEAR(p.temp_c.sem / (spec.temp_noise_c / std::sqrt(n)), 1.0, rel);
    // Slope of a flat trace: 0 within 4 SE over the 60 s window.
    EXPECT_NEAR(p.temp_slope_c_per_min, 0.0, 4 * SlopeSePerMin(spec.temp_noise_c, cfg.average_s));
    EXPECT_NEAR(p.temp_mean_v, 2.5 + 0.009 * 15, 4 * 0.009 * spec.temp_noise_c / std::sqrt(n));
    EXPECT_DOUBLE_EQ(p.supply_mean_v, 5.0);
}

// Samples lost on the network inside the averaging window: the window is refused (with the
// reason), not averaged over the hole, and averaging starts again right after it.
TEST(PlateauDetector, RefusesAWindowWithASequenceGapAndAveragesAgain) {
    // GIVEN a flat 40 degC trace; averaging starts at ~120 s (90 s window + 30 s stable), and
    // 7 samples are lost at 150 s, inside the first averaging window
    const FlatRun run =
        FeedFlat40([](int64_t seq) { return seq >= 15000 && seq < 15007; });  // lost on the network
    const std::vector<Plateau>& got = run.plateaus;
    const std::vector<std::string>& refused = run.refused;
    // THEN one refusal naming the hole, and one plateau that starts after it, without a gap
    ASSERT_EQ(refused.size(), 1u);
    EXPECT_NE(refused[0].find("7 samples missing (sequence gap after seq 14999)"),
              std::string::npos)
        << refused[0];
    EXPECT_NE(refused[0].find("averaging again from seq 15007"), std::string::npos) << refused[0];
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].first_seq, 15007);
    EXPECT_EQ(got[0].seq_gaps, 0);
    EXPECT_EQ(got[0].n_samples, 6001);
    EXPECT_EQ(got[0].last_seq - got[0].first_seq + 1, got[0].n_samples);
}

TEST(PlateauDetector, RearmsOnSetpointChangesAndRunEvents) {
    // GIVEN a plateau at 25 degC, then a run-event setpoint at the same temperature, then the
    // chamber moving to 35 degC with the sensor following (tau = 60 s)
    const double t_change = 700;
    StreamSpec spec;
    spec.temp_true_c = [&](double t) { return FirstOrderLag(t, t_change, 25, 35, 60); };
    Stream stream(spec);
    PlateauDetector det(PlateauConfig::Defaults());
    det.SetChamberSetpoint(25);
    int phase = 0;
    std::vector<State> after_event;
    RunResult r = Feed(
        det, stream, 1400,
        [&](double t) {
            if (phase == 0 && t >= 300) {
                ASSERT_EQ(det.state(), State::kDone);
                det.SetChamberSetpoint(25);  // unchanged: no re-arm
                EXPECT_EQ(det.state(), State::kDone);
                det.OnSetpointEvent(25);  // a run event always re-arms
                EXPECT_EQ(det.state(), State::kWaiting);
                phase = 1;
            }
            if (phase == 1 && t >= t_change) {
                ASSERT_EQ(det.state(), State::kDone);
                det.SetChamberSetpoint(35);
                EXPECT_EQ(det.state(), State::kWaiting);
                phase = 2;
            }
        },
        Still);
    // THEN three plateaus: 25, 25 again, and 35
    ASSERT_EQ(r.plateaus.size(), 3u);
    EXPECT_NEAR(r.plateaus[0].temp_c.mean, 25, 0.01);
    EXPECT_GT(Stream::TimeOf(r.plateaus[1].start_utime), 300);
    EXPECT_NEAR(r.plateaus[1].temp_c.mean, 25, 0.01);
    EXPECT_EQ(r.plateaus[2].setpoint_c, 35);
    // 35 degC plateau: the lag's remaining distance is tau * slope <= 60 s * 0.05/60 degC/s
    // = 0.05 degC (+ the 3-SE slope margin, ~0.004 degC).
    EXPECT_NEAR(r.plateaus[2].temp_c.mean, 35, 0.06);
    // The state report right after each re-arm says "waiting".
    int waiting_reports = 0;
    for (const StateReport& s : r.reports) waiting_reports += s.state == State::kWaiting ? 1 : 0;
    EXPECT_GE(waiting_reports, 3);
}

TEST(PlateauDetector, StampsTheRunInForceAndForgetsItOnStop) {
    // GIVEN a flat trace; a run starts at 0 s and stops at 300 s (both re-arm)
    StreamSpec spec;
    spec.temp_true_c = [](double) { return 25.0; };
    Stream stream(spec);
    PlateauDetector det(PlateauConfig::Defaults());
    det.StartRun("run-A");
    bool stopped = false;
    RunResult r = Feed(
        det, stream, 600,
        [&](double t) {
            if (!stopped && t >= 300) {
                det.EndRun();
                EXPECT_EQ(det.state(), State::kWaiting);
                stopped = true;
            }
        },
        Still);
    // THEN the plateau inside the run carries its id, the one after the stop none
    ASSERT_EQ(r.plateaus.size(), 2u);
    EXPECT_EQ(r.plateaus[0].run_id, "run-A");
    EXPECT_EQ(r.plateaus[1].run_id, "");
    EXPECT_GT(Stream::TimeOf(r.plateaus[1].start_utime), 300);
}

TEST(PlateauDetector, SetpointChangeWithoutTemperatureMoveDoesNotFire) {
    // GIVEN a plateau at 25 degC, then the chamber ordered to 60 degC while the sensor stays at
    // 25 (dead chamber, or the sensor still in its dead time): the flat trace must not pass for
    // the 60 degC plateau.
    StreamSpec spec;
    spec.temp_true_c = [](double) { return 25.0; };
    Stream stream(spec);
    PlateauDetector det(PlateauConfig::Defaults());
    det.SetChamberSetpoint(25);
    bool changed = false;
    RunResult r = Feed(
        det, stream, 1200,
        [&](double t) {
            if (!changed && t >= 300) {
                det.SetChamberSetpoint(60);
                changed = true;
            }
        },
        Still);
    ASSERT_EQ(r.plateaus.size(), 1u);
    EXPECT_EQ(r.plateaus[0].setpoint_c, 25);
    EXPECT_EQ(det.state(), State::kSettling);
}

TEST(PlateauDetector, RearmsByBandWithoutAChamber) {
    // GIVEN CSV-like data, no setpoint at all: flat 25 degC, then a move to 35 (tau 60 s)
    StreamSpec spec;
    spec.temp_true_c = [](double t) { return FirstOrderLag(t, 400, 25, 35, 60); };
    Stream stream(spec);
    PlateauDetector det(PlateauConfig::Defaults());
    RunResult r = Feed(det, stream, 1100, NoHook, Still);
    // THEN the temperature leaving by > 1 degC re-arms it and the second plateau is at 35
    ASSERT_EQ(r.plateaus.size(), 2u);
    EXPECT_TRUE(std::isnan(r.plateaus[1].setpoint_c));
    EXPECT_NEAR(r.plateaus[0].temp_c.mean, 25, 0.01);
    EXPECT_NEAR(r.plateaus[1].temp_c.mean, 35, 0.06);  // as in RearmsOnSetpointChanges
}

TEST(PlateauDetector, StateReportsAtMostTwiceASecondOfDataTimePlusChanges) {
    StreamSpec spec;
    spec.temp_true_c = [](double) { return 25.0; };
    Stream stream(spec);
    PlateauDetector det(PlateauConfig::Defaults());
    RunResult r = Feed(det, stream, 300, NoHook, Still);
    // 300 s at 2 Hz = 600, plus the first and one per state change (3): at most 604
    EXPECT_LE(r.reports.size(), 604u);
    EXPECT_GE(r.reports.size(), 590u);
    std::vector<State> seq;
    for (const StateReport& s : r.reports) {
        if (seq.empty() || seq.back() != s.state) seq.push_back(s.state);
    }
    EXPECT_EQ(seq, (std::vector<State>{State::kWaiting, State::kSettling, State::kAveraging,
                                       State::kDone}));
    EXPECT_EQ(r.reports.back().last_plateau_id, r.plateaus.at(0).plateau_id);
}

TEST(PlateauDetector, CorrelatedGyroNoiseGivesAnHonestSem) {
    // GIVEN AR(1) gyro noise with rho = 0.9 (the module's LPF): the SEM of an n-sample mean is
    // sigma/sqrt(n) * sqrt((1 + rho)/(1 - rho)) = 4.36x the white-noise formula.
    StreamSpec spec;
    spec.temp_true_c = [](double) { return 25.0; };
    spec.gyro_rho = 0.9;
    spec.seed = 21;
    Stream stream(spec);
    const PlateauConfig cfg = PlateauConfig::Defaults();
    PlateauDetector det(cfg);
    RunResult r = Feed(det, stream, 200, NoHook, Still);
    ASSERT_EQ(r.plateaus.size(), 1u);
    const Plateau& p = r.plateaus[0];
    const double n = p.n_samples;
    const double theory = spec.gyro_noise_v / std::sqrt(n) * std::sqrt(1.9 / 0.1);
    // Batch-means relative scatter 1/sqrt(2 (B - 2)) = 0.167: allow 3 of them (the naive
    // formula would be off by 1 - 1/4.36 = 0.77).
    EXPECT_NEAR(p.gyro_v.sem / theory, 1.0, 3 / std::sqrt(2.0 * (cfg.sem_batches - 2)));
}

TEST(PlateauDetector, RejectsInvalidConfig) {
    PlateauConfig c = PlateauConfig::Defaults();
    c.window_s = 0;
    EXPECT_THROW(PlateauDetector{c}, std::invalid_argument);
    gyrocal::testing::ExpectRefusedNaming(
        PlateauConfig::Defaults(), [](auto& c) { c.slope_max_c_per_min = std::nan(""); },
        "slope_max_c_per_min");
    gyrocal::testing::ExpectRefusedNaming(
        PlateauConfig::Defaults(), [](auto& c) { c.sem_batches = 2; }, "sem_batches");
}

}  // namespace
}  // namespace gyrocal::plateau
