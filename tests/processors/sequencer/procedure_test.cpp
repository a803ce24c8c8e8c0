// The procedure state machine: order of commands, waiting on every sensor, data-time timeouts.
#include "processors/sequencer/procedure.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace gyrocal::sequencer {
namespace {

constexpr int64_t kS = 1'000'000;  // us per s

// The help text lists each profile with its own setpoints (it once read freed memory and printed
// garbage for the first two of each).
TEST(Profiles, HelpListsEachProfilesSetpoints) {
    const std::string help = ProfilesHelp();
    EXPECT_NE(help.find("six (25,-40,-10,45,65,85 C)"), std::string::npos) << help;
    EXPECT_NE(help.find("five (-40,-10,25,55,85 C)"), std::string::npos) << help;
    EXPECT_NE(help.find("seed3 (-10,30,60 C)"), std::string::npos) << help;
}

ProcedureOptions TwoSensorsSeed3() {
    ProcedureOptions o;
    o.profile = *NamedProfile("seed3");
    o.sensor_ids = {"A", "B"};
    o.plateau_timeout_s = 600;
    o.rotation_timeout_s = 60;
    return o;
}

template <class T>
int Count(const std::vector<Order>& orders) {
    int n = 0;
    for (const auto& o : orders) n += std::holds_alternative<T>(o) ? 1 : 0;
    return n;
}

std::string FirstEvent(const std::vector<Order>& orders) {
    for (const auto& o : orders)
        if (auto* r = std::get_if<RunEventOrder>(&o)) return r->event;
    return "";
}

TEST(Procedure, RunsTheSeedProcedureInOrder) {
    Procedure p(TwoSensorsSeed3());
    // GIVEN the first data time: the run starts and the chamber is ordered to -10 C
    auto o = p.OnTime(10 * kS);
    ASSERT_EQ(FirstEvent(o), "start");
    ASSERT_EQ(Count<ChamberOrder>(o), 1);
    int chamber_orders = 1, moves = 0;
    double last_move = 0;
    int64_t t = 10 * kS;
    for (int sp = 0; sp < 3; ++sp) {
        EXPECT_EQ(p.phase(), Phase::kWaitPlateau);
        const double sp_c = NamedProfile("seed3")->setpoints_c[sp];
        // WHEN only one sensor has settled THEN nothing moves yet
        EXPECT_TRUE(p.OnPlateau("A", t += kS, sp_c).empty());
        auto after = p.OnPlateau("B", t += kS, sp_c);
        ASSERT_EQ(Count<TurntableOrder>(after), 1) << "rotation after both plateaus";
        last_move = std::get<TurntableOrder>(after[1]).move_deg;
        EXPECT_EQ(last_move, 90.0);
        ++moves;
        EXPECT_TRUE(p.OnSensitivity("B", t += kS).empty());
        after = p.OnSensitivity("A", t += kS);
        ASSERT_EQ(Count<TurntableOrder>(after), 1);
        EXPECT_EQ(std::get<TurntableOrder>(after[1]).move_deg, -90.0);
        ++moves;
        p.OnSensitivity("A", t += kS);
        after = p.OnSensitivity("B", t += kS);
        if (sp < 2) {
            ASSERT_EQ(Count<ChamberOrder>(after), 1);
            ++chamber_orders;
        } else {
            EXPECT_EQ(FirstEvent(after), "stop");
        }
    }
    EXPECT_EQ(chamber_orders, 3);
    EXPECT_EQ(moves, 6);
    EXPECT_TRUE(p.done());
    EXPECT_EQ(p.outcome(), "completed");
}

TEST(Procedure, StalePlateausAndOtherSetpointsDoNotCount) {
    Procedure p(TwoSensorsSeed3());
    p.OnTime(100 * kS);
    EXPECT_TRUE(p.OnPlateau("A", 50 * kS, -10.0).empty());  // ended before the order
    EXPECT_TRUE(p.OnPlateau("B", 200 * kS, 25.0).empty());  // a plateau of another setpoint
    EXPECT_EQ(p.pending_sensors(), (std::set<std::string>{"A", "B"}));
    p.OnPlateau("A", 200 * kS, NAN);  // unknown setpoint (CSV data): counts
    EXPECT_EQ(p.pending_sensors(), (std::set<std::string>{"B"}));
}

TEST(Procedure, MissingPlateauEndsTheRunAsChamberFaultOnDataTime) {
    Procedure p(TwoSensorsSeed3());
    p.OnTime(0);
    p.OnPlateau("A", 10 * kS, -10.0);
    EXPECT_TRUE(p.OnTime(600 * kS).empty()) << "exactly at the timeout it still waits";
    auto o = p.OnTime(601 * kS);
    ASSERT_EQ(FirstEvent(o), "abort");
    EXPECT_TRUE(p.done());
    EXPECT_EQ(p.outcome(), "abort");
    EXPECT_NE(p.outcome_reason().find("chamber fault"), std::string::npos);
    EXPECT_NE(p.outcome_reason().find("B"), std::string::npos) << p.outcome_reason();
    EXPECT_EQ(p.outcome_reason().find("A,"), std::string::npos) << "A did settle";
    EXPECT_TRUE(p.OnTime(700 * kS).empty()) << "nothing after the end";
}

TEST(Procedure, MissingSensitivityIsNotedAndTheRunGoesOn) {
    ProcedureOptions opt = TwoSensorsSeed3();
    opt.profile = Profile{"one", {25.0}};
    opt.move_attempts = 1;  // no second order: the note comes at once
    Procedure p(opt);
    p.OnTime(0);
    p.OnPlateau("A", kS, 25.0);
    p.OnPlateau("B", kS, 25.0);
    ASSERT_EQ(p.phase(), Phase::kWaitRotation);
    p.OnSensitivity("A", 2 * kS);
    auto o = p.OnTime(62 * kS);  // B never reported the +90 move
    ASSERT_EQ(Count<TurntableOrder>(o), 1);
    ASSERT_EQ(p.notes().size(), 1u);
    EXPECT_NE(p.notes()[0].find("B"), std::string::npos);
}

// A turn that lost samples on the network is rejected by the estimator; the sequencer orders the
// same move again, and only after the last attempt notes it as missing (in the stop reason too).
TEST(Procedure, RejectedMoveIsOrderedAgainThenNamedAsMissing) {
    ProcedureOptions opt = TwoSensorsSeed3();
    opt.profile = Profile{"one", {25.0}};
    opt.move_attempts = 2;
    Procedure p(opt);
    p.OnTime(0);
    p.OnPlateau("A", kS, 25.0);
    auto o = p.OnPlateau("B", kS, 25.0);
    ASSERT_EQ(Count<TurntableOrder>(o), 1);
    EXPECT_DOUBLE_EQ(std::get<TurntableOrder>(o[1]).move_deg, 90.0);
    // WHEN B's +90 point is rejected for a hole THEN +90 is ordered again after 10 s of data at
    // rest (the default retry_wait_s: a rest window before the turn), saying why
    p.OnSensitivity("A", 2 * kS, true);
    EXPECT_TRUE(p.OnSensitivity("B", 3 * kS, false, "12 samples missing (sequence gaps)").empty());
    EXPECT_EQ(p.phase(), Phase::kWaitRetry);
    EXPECT_TRUE(p.OnTime(12 * kS).empty());
    o = p.OnTime(13 * kS);
    ASSERT_EQ(Count<TurntableOrder>(o), 1);
    EXPECT_DOUBLE_EQ(std::get<TurntableOrder>(o[1]).move_deg, 90.0);
    const auto& ev = std::get<RunEventOrder>(o[0]);
    EXPECT_NE(ev.reason.find("attempt 2 of 2 after B: rejected: 12 samples missing"),
              std::string::npos)
        << ev.reason;
    EXPECT_TRUE(p.notes().empty());
    // A point of the first attempt arriving late does not count for the second.
    EXPECT_TRUE(p.OnSensitivity("A", 2 * kS, true).empty());
    EXPECT_EQ(p.pending_sensors(), (std::set<std::string>{"A", "B"}));
    // WHEN both accept on the second attempt THEN the run moves on to -90
    p.OnSensitivity("A", 14 * kS, true);
    o = p.OnSensitivity("B", 14 * kS, true);
    ASSERT_EQ(Count<TurntableOrder>(o), 1);
    EXPECT_DOUBLE_EQ(std::get<TurntableOrder>(o[1]).move_deg, -90.0);
    // WHEN -90 fails twice (B silent, then rejected) THEN it is noted and the run completes naming
    // it
    p.OnSensitivity("A", 15 * kS, true);
    EXPECT_TRUE(p.OnTime(14 * kS + 61 * kS).empty());  // B silent past the 60 s rotation timeout
    o = p.OnTime(14 * kS + 71 * kS);
    ASSERT_EQ(Count<TurntableOrder>(o), 1);
    p.OnSensitivity("A", 90 * kS, true);
    o = p.OnSensitivity("B", 91 * kS, false, "slip");
    EXPECT_EQ(FirstEvent(o), "stop");
    ASSERT_EQ(p.notes().size(), 1u);
    EXPECT_NE(p.notes()[0].find("move -90 deg at setpoint 25 degC"), std::string::npos)
        << p.notes()[0];
    EXPECT_NE(p.notes()[0].find("after 2 attempts (B: rejected: slip)"), std::string::npos)
        << p.notes()[0];
    EXPECT_EQ(p.outcome(), "completed");
    EXPECT_EQ(p.outcome_reason().rfind("completed; missing: move -90 deg", 0), 0u)
        << p.outcome_reason();
}

// A restarted sequencer resumes its run at the setpoint it was at: no second start, that
// setpoint ordered again, the ones after it follow.
TEST(Procedure, ResumeTakesTheSetpointAgainWithoutAStart) {
    ProcedureOptions opt = TwoSensorsSeed3();
    opt.resume_setpoint_index = 1;
    Procedure p(opt);
    auto o = p.OnTime(100 * kS);
    ASSERT_EQ(FirstEvent(o), "setpoint");
    ASSERT_EQ(Count<ChamberOrder>(o), 1);
    EXPECT_DOUBLE_EQ(std::get<ChamberOrder>(o[1]).setpoint_c, 30.0);
    EXPECT_EQ(p.setpoint_index(), 1);
    EXPECT_EQ(std::get<RunEventOrder>(o[0]).setpoint_index, 1);
}

// A supervisor's abort of the run ends the procedure without further orders.
TEST(Procedure, EndedElsewhereOrdersNothingMore) {
    Procedure p(TwoSensorsSeed3());
    p.OnTime(0);
    p.EndedElsewhere("abort", "gyrocal-sim-rig died");
    EXPECT_TRUE(p.done());
    EXPECT_EQ(p.outcome(), "abort");
    EXPECT_EQ(p.outcome_reason(), "gyrocal-sim-rig died");
    EXPECT_TRUE(p.OnTime(10 * kS).empty());
    EXPECT_TRUE(p.Abort("operator stop").empty()) << "no second end event";
}

TEST(Procedure, AbortByOperatorIsRecorded) {
    Procedure p(TwoSensorsSeed3());
    p.OnTime(0);
    auto o = p.Abort("operator stop (signal)");
    EXPECT_EQ(FirstEvent(o), "abort");
    EXPECT_EQ(p.outcome_reason(), "operator stop (signal)");
}

TEST(ProcedureOptions, RefusesWhatCannotBeDoneWithTheValidRange) {
    auto expect_refused = [](ProcedureOptions o, const std::string& needle) {
        try {
            Procedure p(o);
            ADD_FAILURE() << "accepted; expected refusal mentioning " << needle;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    ProcedureOptions o = TwoSensorsSeed3();
    o.ramp_rate_c_per_min = 0;
    expect_refused(o, "valid is (0, 30]");
    o = TwoSensorsSeed3();
    o.profile.setpoints_c = {25, NAN};
    expect_refused(o, "valid is -60..150");
    o = TwoSensorsSeed3();
    o.sensor_ids.clear();
    expect_refused(o, "sensor");
    o = TwoSensorsSeed3();
    o.retry_wait_s = -1;
    expect_refused(o, "retry wait -1 s: valid is 0..600");
    o = TwoSensorsSeed3();
    o.move_attempts = 6;
    expect_refused(o, "valid is 1..5");
    o = TwoSensorsSeed3();
    o.resume_setpoint_index = 3;
    expect_refused(o, "valid is 0..2");
    o = TwoSensorsSeed3();
    o.moves_deg = {0};
    expect_refused(o, "without 0");
    EXPECT_FALSE(NamedProfile("nope").has_value());
}

}  // namespace
}  // namespace gyrocal::sequencer
