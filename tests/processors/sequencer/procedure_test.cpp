// The procedure state machine: order of commands, waiting on every sensor, data-time timeouts.
#include <gtest/gtest.h>

#include <cmath>

#include "procedure.hpp"

namespace gyrocal::sequencer {
namespace {

constexpr int64_t kS = 1'000'000;  // us per s

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
    o.moves_deg = {0};
    expect_refused(o, "without 0");
    EXPECT_FALSE(NamedProfile("nope").has_value());
}

}  // namespace
}  // namespace gyrocal::sequencer
