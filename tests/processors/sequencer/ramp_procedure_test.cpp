// The ramp procedure: legs through the waypoints without waiting for stability, turn pairs on a
// data-time schedule, the dwell, timeouts, the early stop on coefficient uncertainty, and the
// uncertainty figure itself.
#include "processors/sequencer/ramp_procedure.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "processors/sequencer/coeff_uncertainty.hpp"

namespace gyrocal::sequencer {
namespace {

constexpr int64_t kS = 1'000'000;  // us per s

ProcedureOptions Ramp(std::vector<double> waypoints = {10.0, 40.0}) {
    ProcedureOptions o;
    o.profile = Profile{"ramp", std::move(waypoints), true};
    o.sensor_ids = {"A", "B"};
    o.ramp_rate_c_per_min = 3.0;
    o.turn_interval_s = 120.0;
    o.dwell_s = 60.0;
    o.rotation_timeout_s = 30.0;
    o.plateau_timeout_s = 3600.0;
    return o;
}

template <class T>
std::vector<T> All(const std::vector<Order>& orders) {
    std::vector<T> out;
    for (const auto& o : orders)
        if (const auto* x = std::get_if<T>(&o)) out.push_back(*x);
    return out;
}

// Drives a simulated chamber that follows the order at the ramp rate; answers every move from
// both sensors 5 s after it was ordered. Returns every order, in order.
struct Driver {
    RampProcedure& p;
    double air_c = 25.0, target_c = 25.0;
    int64_t t = 0;
    int64_t move_answer_utime = -1;
    std::vector<Order> all{};
    void Take(const std::vector<Order>& o) {
        for (const auto& c : All<ChamberOrder>(o)) target_c = c.setpoint_c;
        if (!All<TurntableOrder>(o).empty()) move_answer_utime = t + 5 * kS;
        all.insert(all.end(), o.begin(), o.end());
    }
    void Step() {
        t += kS;
        const double step = 3.0 / 60.0;
        air_c += std::clamp(target_c - air_c, -step, step);
        Take(p.OnChamber(t, air_c));
        if (move_answer_utime >= 0 && t >= move_answer_utime) {
            move_answer_utime = -1;
            Take(p.OnSensitivity("A", t));
            Take(p.OnSensitivity("B", t));
        }
    }
};

TEST(RampProcedure, RampsThroughTheWaypointsTurningOnTheMoveWithoutWaiting) {
    RampProcedure p(Ramp());
    Driver d{p};
    while (!p.done() && d.t < 4 * 3600 * kS) d.Step();
    ASSERT_TRUE(p.done());
    EXPECT_EQ(p.outcome(), "completed") << p.outcome_reason();
    const auto chamber = All<ChamberOrder>(d.all);
    ASSERT_EQ(chamber.size(), 2u);
    EXPECT_EQ(chamber[0].setpoint_c, 10.0);
    EXPECT_EQ(chamber[1].setpoint_c, 40.0);
    EXPECT_EQ(chamber[0].ramp_rate_c_per_min, 3.0);
    // Plan: a leg ends once the air is within the 1 degC reach band: 14 + 29 degC at 3 degC/min
    // = 860 s, plus two dwells of 60 s: 980 s of data (+ up to the 5 s of a turn under way).
    const double end_s = static_cast<double>(d.t) / kS;
    EXPECT_NEAR(end_s, 980.0, 6.0);
    // A +90/-90 pair 30 s in and then every 120 s.
    const auto moves = All<TurntableOrder>(d.all);
    ASSERT_EQ(moves.size() % 2, 0u);
    EXPECT_EQ(p.turns_done(), static_cast<int>(moves.size() / 2));
    EXPECT_EQ(p.turns_done(), static_cast<int>(std::floor((end_s - 30.0) / 120.0)) + 1);
    EXPECT_EQ(moves[0].move_deg, 90.0);
    EXPECT_EQ(moves[1].move_deg, -90.0);
    EXPECT_TRUE(p.notes().empty());
}

TEST(RampProcedure, AMissingPointIsNotedAndTheRampGoesOn) {
    RampProcedure p(Ramp());
    int64_t t = 0;
    p.OnChamber(t, 25.0);
    // The first pair is ordered 30 s in; only A answers, B never does.
    std::vector<TurntableOrder> moves;
    for (; t <= 31 * kS; t += kS)
        for (const auto& m : All<TurntableOrder>(p.OnChamber(t, 25.0))) moves.push_back(m);
    ASSERT_EQ(moves.size(), 1u);
    p.OnSensitivity("A", t);
    // After the rotation timeout (30 s) the -90 move is ordered anyway.
    for (; t <= 70 * kS; t += kS)
        for (const auto& m : All<TurntableOrder>(p.OnChamber(t, 25.0))) moves.push_back(m);
    ASSERT_EQ(moves.size(), 2u);
    EXPECT_EQ(moves[1].move_deg, -90.0);
    ASSERT_EQ(p.notes().size(), 1u);
    EXPECT_NE(p.notes()[0].find("B"), std::string::npos) << p.notes()[0];
    EXPECT_FALSE(p.done());
}

TEST(RampProcedure, AChamberThatNeverGetsThereAbortsTheRun) {
    ProcedureOptions o = Ramp();
    o.plateau_timeout_s = 600.0;
    RampProcedure p(o);
    std::vector<Order> last;
    for (int64_t t = 0; t <= 700 * kS && !p.done(); t += kS) last = p.OnChamber(t, 25.0);
    ASSERT_TRUE(p.done());
    EXPECT_EQ(p.outcome(), "abort");
    EXPECT_NE(p.outcome_reason().find("did not reach 10 degC"), std::string::npos)
        << p.outcome_reason();
    ASSERT_EQ(All<RunEventOrder>(last).size(), 1u);
    EXPECT_EQ(All<RunEventOrder>(last)[0].event, "abort");
}

TEST(RampProcedure, StopsEarlyOnlyOnceBothDirectionsAreInAndEveryUnitMeetsTheTarget) {
    ProcedureOptions o = Ramp();
    o.target_offset_dps = 0.05;
    RampProcedure p(o);
    Driver d{p};
    const CoeffUncertainty good{0.01, 1.0}, bad{0.2, 1.0};
    // First leg (cooling only): a good set does not stop the run.
    for (int i = 0; i < 60; ++i) d.Step();
    d.Take(p.OnCoefficients("A", d.t, good));
    d.Take(p.OnCoefficients("B", d.t, bad));
    d.Take(p.OnCoefficients("B", d.t, good));
    d.Step();
    EXPECT_FALSE(p.done());
    d.Take(p.OnCoefficients("B", d.t, bad));
    while (p.setpoint_index() < 1) d.Step();  // the heating leg has begun
    d.Take(p.OnCoefficients("A", d.t, good));
    for (int i = 0; i < 10; ++i) d.Step();
    EXPECT_FALSE(p.done()) << "B is not there yet";
    d.Take(p.OnCoefficients("B", d.t, good));
    for (int i = 0; i < 20 && !p.done(); ++i) d.Step();  // a turn under way finishes first
    ASSERT_TRUE(p.done());
    EXPECT_EQ(p.outcome(), "completed");
    EXPECT_NE(p.outcome_reason().find("target reached"), std::string::npos) << p.outcome_reason();
    // Saved: the rest of the heating leg from where the air was (~40 - air at 3 degC/min) and
    // its dwell.
    EXPECT_GT(p.saved_s(), 60.0);
    EXPECT_LE(p.saved_s(), 30.0 / 3.0 * 60.0 + 60.0);
    EXPECT_NE(p.outcome_reason().find("chamber time saved"), std::string::npos);
}

TEST(RampProcedure, WithoutATargetTheCoefficientsChangeNothing) {
    RampProcedure p(Ramp());
    Driver d{p};
    while (p.setpoint_index() < 1) d.Step();
    d.Take(p.OnCoefficients("A", d.t, {1e-6, 1e-6}));
    d.Take(p.OnCoefficients("B", d.t, {1e-6, 1e-6}));
    d.Step();
    EXPECT_FALSE(p.done());
}

TEST(RampProcedure, BadOptionsNameTheField) {
    auto refused = [](auto change, const std::string& says) {
        ProcedureOptions o = Ramp();
        change(o);
        try {
            RampProcedure p(o);
            ADD_FAILURE() << "accepted; expected: " << says;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
        }
    };
    refused([](ProcedureOptions& o) { o.turn_interval_s = 5; }, "turn interval");
    refused([](ProcedureOptions& o) { o.dwell_s = -1; }, "dwell");
    refused([](ProcedureOptions& o) { o.reach_band_c = 0; }, "reach band");
    refused([](ProcedureOptions& o) { o.target_offset_dps = NAN; }, "target offset");
    refused([](ProcedureOptions& o) { o.target_sensitivity_pct = 101; }, "target sensitivity");
    refused([](ProcedureOptions& o) { o.profile.continuous = false; }, "continuous profile");
    refused([](ProcedureOptions& o) { o.resume_setpoint_index = 0; }, "cannot be resumed");
    EXPECT_NE(dynamic_cast<RampProcedure*>(MakeRunner(Ramp()).get()), nullptr);
    ProcedureOptions plateau = Ramp();
    plateau.profile.continuous = false;
    EXPECT_NE(dynamic_cast<Procedure*>(MakeRunner(plateau).get()), nullptr);
}

model::Model Poly(const std::string& quantity, std::vector<double> c, Eigen::MatrixXd cov) {
    model::Model m;
    m.quantity = quantity;
    m.term_names = {"1", "dT", "dT^2"};
    m.coeffs = Eigen::Map<Eigen::VectorXd>(c.data(), 3);
    m.covariance = std::move(cov);
    m.t0_c = 25.0;
    m.temp_min_c = 0.0;
    m.temp_max_c = 50.0;
    return m;
}

TEST(CoeffUncertainty, IsTheWorstOneSigmaOverTheRangeRelativeToTheSensitivity) {
    // GIVEN offset sd 1e-4 V in the constant and 1e-6 V/K in the slope (no correlation) and a
    // sensitivity of 5 mV/(deg/s) known to 5e-6 V/(deg/s) in its constant
    Eigen::MatrixXd co = Eigen::MatrixXd::Zero(3, 3), cs = Eigen::MatrixXd::Zero(3, 3);
    co(0, 0) = 1e-8;
    co(1, 1) = 1e-12;
    cs(0, 0) = 25e-12;
    model::CoeffSet set;
    set.offset = Poly("offset_v", {2.5, 1e-4, 0.0}, co);
    set.sensitivity = Poly("sensitivity_v_per_dps", {5e-3, 0.0, 0.0}, cs);
    // WHEN taken over -40..85 degC (beyond the fitted 0..50: extrapolated)
    const CoeffUncertainty u = UncertaintyOver(set, -40.0, 85.0);
    // THEN the worst is at -40 (dT = -65): sqrt(1e-8 + 65^2 1e-12) / 5e-3, and 0.1 %
    EXPECT_NEAR(u.offset_dps, std::sqrt(1e-8 + 65.0 * 65.0 * 1e-12) / 5e-3, 1e-9);
    EXPECT_NEAR(u.sensitivity_pct, 0.1, 1e-9);
    // An unknown covariance gives no figure (never a pass).
    set.offset.covariance(0, 0) = NAN;
    EXPECT_TRUE(std::isnan(UncertaintyOver(set, -40.0, 85.0).offset_dps));
    EXPECT_THROW(UncertaintyOver(set, 10.0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace gyrocal::sequencer
