// The virtual lab (in-process calibration pipeline) against the rig's truth.
//
// Tolerances come from the noise model of the rig (sim/config.hpp, sim/noise.hpp):
// - A plateau mean of the gyro carries (a) the white/fast noise, which its own SEM (batch means)
//   states, and (b) noise too slow to vary inside a 60 s window, which it cannot state: the
//   bias-instability Gauss-Markov components of 10, 100 and 1000 s (sigma q each) and the rate
//   random walk accumulated since power-on, K sqrt(t). So sigma_slow^2 = 3 q^2 + K^2 t_run, in
//   volts times the sensitivity. And (c) the temperature sensor's lag: the plateau criterion lets
//   the temperature move 0.05 degC/min, the sensor lags the die by sensor_tau (15 s), so the
//   measured mean is off the die mean by <= 0.05/60*15 degC; times the steepest offset slope of a
//   unit (o1_max + 2 o2_max * 65 K) that is a bound, added linearly.
//   Bound: |V_plateau - offset_true(T_meas - sensor_offset)| <= 4.5 sqrt(sem^2 + slow^2) + lag.
//   4.5 sigma: with ~20 comparisons per test, a false alarm has probability ~1e-4.
// - A sensitivity point states its own standard error (offset and noise propagated); the slow
//   noise is removed by its straight-line offset through the rest windows either side, so
//   |S_point - S_true(T_point - sensor_offset)| <= 4.5 stderr.
#include "tests/support/virtual_lab/virtual_lab.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "producers/sim/noise.hpp"
#include "tests/support/virtual_lab/held_out.hpp"

namespace gyrocal::virtual_lab {
namespace {

constexpr double kSigmas = 4.5;

// [V] the slow-noise standard deviation of a plateau mean (see the header comment).
double SlowNoiseV(const sim::RigConfig& rig, double t_run_s, double sens_v_per_dps) {
    const double q = sim::BiasInstabilityComponentSigma(rig.noise.bias_instability_dps);
    const double k = rig.noise.rate_random_walk_dps_rts;
    return std::sqrt(3 * q * q + k * k * t_run_s) * sens_v_per_dps;
}

// [V] bound on the offset error from the temperature sensor's lag at the plateau slope limit.
double LagBoundV(const LabConfig& c) {
    const double lag_c = c.plateau.slope_max_c_per_min / 60.0 * c.rig.thermal.sensor_tau_s;
    const double slope_v_per_c =
        c.rig.spread.offset_tc_max_v_per_c + 2 * c.rig.spread.offset_tc2_max_v_per_c2 * 65.0;
    return lag_c * slope_v_per_c;
}

const sim::UnitTruth& TruthOf(const RunResult& r, const std::string& id) {
    for (const auto& u : r.truths)
        if (u.sensor_id == id) return u;
    throw std::runtime_error("no truth for " + id);
}

LabConfig SmallLab(const std::string& profile, fit::Method method, uint64_t seed) {
    LabConfig c = LabConfig::For(profile, method);
    c.rig.seed = seed;
    c.rig.num_units = 2;
    return c;
}

void ExpectPointsMatchTruth(const LabConfig& c, const RunResult& r) {
    const double t_run_s = 1e-6 * static_cast<double>(r.end_utime - c.rig.start_utime);
    for (const auto& p : r.plateaus) {
        const sim::UnitTruth& u = TruthOf(r, p.sensor_id);
        const double die_c = p.temp_mean_c - u.temp_sensor_offset_c;
        const double slow = SlowNoiseV(c.rig, t_run_s, u.SensitivityVPerDps(die_c));
        const double tol = kSigmas * std::hypot(p.gyro_sem_v, slow) + LagBoundV(c);
        EXPECT_NEAR(p.gyro_mean_v, u.OffsetV(die_c), tol)
            << p.sensor_id << " plateau at " << p.temp_mean_c << " degC";
    }
    for (const auto& s : r.sensitivity_points) {
        ASSERT_TRUE(s.accepted) << s.sensor_id << ": " << s.reject_reason;
        const sim::UnitTruth& u = TruthOf(r, s.sensor_id);
        const double die_c = s.temp_c - u.temp_sensor_offset_c;
        EXPECT_NEAR(s.sensitivity_v_per_dps, u.SensitivityVPerDps(die_c),
                    kSigmas * s.sensitivity_stderr_v_per_dps)
            << s.sensor_id << " rotation at " << s.temp_c << " degC, direction "
            << int(s.direction);
    }
}

TEST(VirtualLab, SeedThreePointRunReproducesTheTruthAtEveryPoint) {
    // GIVEN the seed's profile and method on two simulated units
    const LabConfig c = SmallLab("seed3", fit::Method::kThreePoint, 11);
    // WHEN the whole procedure runs in-process
    const RunResult r = virtual_lab::Run(c);
    // THEN it completes with one plateau per setpoint and +-90 deg points per setpoint and sensor
    ASSERT_EQ(r.outcome, "completed") << r.outcome_reason;
    ASSERT_EQ(r.plateaus.size(), 3u * 2u);
    ASSERT_EQ(r.sensitivity_points.size(), 3u * 2u * 2u);
    for (const auto& p : r.plateaus) {
        EXPECT_TRUE(std::find(c.procedure.profile.setpoints_c.begin(),
                              c.procedure.profile.setpoints_c.end(),
                              p.setpoint_c) != c.procedure.profile.setpoints_c.end());
        EXPECT_EQ(p.run_id, c.run_id);
    }
    ExpectPointsMatchTruth(c, r);
    // AND each sensor's final set is the seed's 3-point solution through its plateaus
    ASSERT_EQ(r.final_sets.size(), 2u);
    for (const auto& [id, set] : r.final_sets) {
        EXPECT_EQ(set.offset.method, "3point");
        EXPECT_EQ(set.sensitivity.method, "3point");
        EXPECT_EQ(set.plateau_ids.size(), 3u);
        EXPECT_EQ(set.rotation_ids.size(), 6u);
        const model::Evaluator off(set.offset);
        for (const auto& p : r.plateaus) {
            if (p.sensor_id != id) continue;
            model::ModelInputs in;
            in.temp_c = p.temp_mean_c;
            // exact to rounding: 3 points, 3 coefficients (1e-9 V = ~1e5 ulp of 2.5 V)
            EXPECT_NEAR(off.Value(in, model::RangePolicy::kClip), p.gyro_mean_v, 1e-9);
        }
    }
    // AND the chamber time is at least the pure ramp time of the profile at the ordered ramp rate
    double ramp_c = 0, from_c = c.rig.thermal.start_temp_c;
    for (double t : c.procedure.profile.setpoints_c) {
        ramp_c += std::abs(t - from_c);
        from_c = t;
    }
    EXPECT_GT(r.chamber_hours(), ramp_c / c.procedure.ramp_rate_c_per_min / 60.0);
    EXPECT_LE(r.chamber_hours() * 3600.0, 1e-6 * (r.end_utime - c.rig.start_utime) + 1e-9);
}

TEST(VirtualLab, FivePointWlsCurveFollowsTheTruthAcrossItsRange) {
    // GIVEN the default 5-point profile and the N-point fit
    const LabConfig c = SmallLab("five", fit::Method::kWls, 5);
    const RunResult r = virtual_lab::Run(c);
    ASSERT_EQ(r.outcome, "completed") << r.outcome_reason;
    ASSERT_EQ(r.plateaus.size(), 5u * 2u);
    ExpectPointsMatchTruth(c, r);
    // THEN the fitted offset curve follows the truth within its stated uncertainty plus the slow
    // noise (which the plateau SEMs, and so the covariance, do not contain; each plateau carries
    // its own, so the curve between them carries about as much: one more sigma_slow).
    const double t_run_s = 1e-6 * static_cast<double>(r.end_utime - c.rig.start_utime);
    for (const auto& [id, set] : r.final_sets) {
        EXPECT_EQ(set.offset.method, "wls");
        const sim::UnitTruth& u = TruthOf(r, id);
        const model::Evaluator off(set.offset);
        for (double t = set.offset.temp_min_c; t <= set.offset.temp_max_c; t += 5.0) {
            model::ModelInputs in;
            in.temp_c = t;
            const model::Evaluation e = off.Evaluate(in, model::RangePolicy::kClip);
            const double die_c = t - u.temp_sensor_offset_c;
            const double slow = SlowNoiseV(c.rig, t_run_s, u.SensitivityVPerDps(die_c));
            EXPECT_NEAR(e.value, u.OffsetV(die_c),
                        kSigmas * std::sqrt(e.variance + slow * slow) + LagBoundV(c))
                << id << " at " << t << " degC";
        }
    }
}

TEST(VirtualLab, HeldOutWithTheTruthLeavesExactlyTheFloorAndTheSeedClipsOutsideItsRange) {
    // GIVEN a seed-method calibration and the truth of the same units
    LabConfig c = SmallLab("seed3", fit::Method::kThreePoint, 3);
    const RunResult r = virtual_lab::Run(c);
    ASSERT_EQ(r.outcome, "completed") << r.outcome_reason;
    Candidate truth;
    for (const auto& u : r.truths) truth[u.sensor_id] = TruthSet(u, -60.0, 150.0);
    HeldOutProfile p;
    p.waypoints_c = {-40.0, 85.0};
    p.ramp_c_per_min = 2.0;
    p.hold_s = 300.0;
    p.lead_in_s = 1e-6 * static_cast<double>(r.end_utime - c.rig.start_utime);
    // WHEN a held-out profile is compensated with both
    const HeldOutResult h = EvaluateHeldOut(c.rig, p, {r.final_sets, truth});
    ASSERT_EQ(h.sensors.size(), 2u);
    const double white_bin_dps = c.rig.noise.noise_density_dps_rthz / std::sqrt(h.bin_s);
    const double q = sim::BiasInstabilityComponentSigma(c.rig.noise.bias_instability_dps);
    const double k = c.rig.noise.rate_random_walk_dps_rts;
    for (const SensorHeldOut& s : h.sensors) {
        ASSERT_GT(s.t_s.size(), 100u);
        // THEN the truth through the compensator is the floor at the measured temperature, bin by
        // bin (the same arithmetic by two routes: only rounding differs)
        for (size_t i = 0; i < s.t_s.size(); ++i)
            ASSERT_NEAR(s.err_dps[1][i], s.floor_meas_dps[i], 1e-9) << s.sensor_id << " bin " << i;
        // AND the floor is the rig's noise at the bin length: at least the white part (minus the
        // chi-square scatter of ~1000 bins, a few %), at most white + the 4 Gauss-Markov
        // components + the random walk over the whole record, with 50 % margin for the sampling
        // of such slow terms over one record.
        const Score f =
            ScoreBins(s.floor_dps, s.temp_c, -1e9, 1e9, s.floor_angle_deg, h.duration_s);
        const double t_total_s = p.lead_in_s + h.duration_s;
        EXPECT_GT(f.rms_dps, 0.9 * white_bin_dps);
        EXPECT_LT(f.rms_dps,
                  1.5 * std::sqrt(white_bin_dps * white_bin_dps + 4 * q * q + k * k * t_total_s));
        // AND the seed's set, clipped outside -10..60 degC, errs more outside its range than in it
        const model::CoeffSet& set = r.final_sets.at(s.sensor_id);
        const Score e = ScoreBins(s.err_dps[0], s.temp_c, set.offset.temp_min_c,
                                  set.offset.temp_max_c, s.angle_deg[0], h.duration_s);
        EXPECT_GT(e.bins_in, 0);
        EXPECT_GT(e.bins_out, 0);
        EXPECT_GT(e.max_out_dps, e.max_in_dps) << s.sensor_id;
        EXPECT_EQ(s.not_compensated[0], 0);
    }
}

TEST(VirtualLab, RefusesBadConfigurationAndCutsARunThatCannotFinish) {
    EXPECT_THROW(LabConfig::For("eleven", fit::Method::kWls), std::invalid_argument);
    LabConfig c = SmallLab("seed3", fit::Method::kThreePoint, 1);
    c.rig.num_units = 0;
    EXPECT_THROW(virtual_lab::Run(c), sim::ConfigError);
    c = SmallLab("seed3", fit::Method::kThreePoint, 1);
    c.procedure.profile.setpoints_c = {-10.0, 30.0, 200.0};  // the procedure refuses > 150 degC
    EXPECT_THROW(virtual_lab::Run(c), std::invalid_argument);
    c = SmallLab("seed3", fit::Method::kThreePoint, 1);
    c.procedure.profile.setpoints_c = {-10.0, 120.0};  // valid for the procedure, not the chamber
    c.procedure.plateau_timeout_s = 1800;
    const RunResult refused = virtual_lab::Run(c);
    EXPECT_EQ(refused.outcome, "abort");
    EXPECT_NE(refused.outcome_reason.find("chamber fault"), std::string::npos)
        << refused.outcome_reason;
    ASSERT_FALSE(refused.notes.empty());
    EXPECT_NE(refused.notes.front().find("chamber refused"), std::string::npos);
    c = SmallLab("seed3", fit::Method::kThreePoint, 1);
    c.max_sim_s = 600;
    const RunResult cut = virtual_lab::Run(c);
    EXPECT_EQ(cut.outcome, "cut");
    EXPECT_TRUE(cut.final_sets.empty());

    HeldOutProfile p;
    p.waypoints_c = {-40.0, 120.0};
    EXPECT_THROW(p.Validate(c.rig), std::invalid_argument);
    p.waypoints_c = {-40.0};
    p.bin_s = 0.005;
    EXPECT_THROW(p.Validate(c.rig), std::invalid_argument);
}

}  // namespace
}  // namespace gyrocal::virtual_lab
