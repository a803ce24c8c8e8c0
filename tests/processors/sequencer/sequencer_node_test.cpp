// gyrocal-sequencer's node in one process over memq:// (LCM's in-process provider): it discovers
// the units from their GYRO_ channels, starts the run, orders the chamber to each setpoint, turns
// the table once every unit has its plateau and goes on once every unit has its sensitivity
// point, then stops "completed"; messages it must not act on (a unit it does not await, a plateau
// of another setpoint, a chamber fault) change nothing but what they should. Data time only: the
// test moves it with gyro samples, no sleep and no wall clock.
#include "processors/sequencer/node/sequencer_node.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/lcmtypes/bus/wire.hpp"
#include "tests/lcmtypes/message_builders.hpp"

namespace gyrocal::sequencer::node {
namespace {

using gyrocal::testing::kT0Utime;

class MemqSequencer {
public:
    MemqSequencer() : node_(Options()), wire_(gyrocal::testing::ForNode(node_)) {
        bus::Bus& bus = node_.bus();
        gyrocal::testing::CollectInto(bus, std::string(channels::kRunEvent), events);
        gyrocal::testing::CollectInto(bus, std::string(channels::kChamberCmd), chamber);
        gyrocal::testing::CollectInto(bus, std::string(channels::kTurntableCmd), turns);
    }
    static SequencerOptions Options() {
        SequencerOptions o = SequencerOptions::Defaults();
        o.lcm_url = "memq://";
        o.run_id = "run-seq";
        o.discover_s = 2.0;
        o.procedure.profile = Profile{"two", {30.0, 40.0}, false};
        return o;
    }
    // Data time moves to `t_s` [s after kT0Utime] through gyro samples of both units (10 Hz).
    void AdvanceTo(double t_s) {
        for (; now_s_ <= t_s; now_s_ += 0.1) {
            ++seq_;
            for (const char* id : {"S01", "S02"})
                node_.bus().Publish(channels::Gyro(id),
                                    gyrocal::testing::GyroSample(id, Utime(now_s_), seq_, 2.5, 25));
        }
        wire_.pace();
    }
    static int64_t Utime(double t_s) { return kT0Utime + static_cast<int64_t>(t_s * 1e6); }
    void PlateauOf(const std::string& id, double setpoint_c) {
        plateau_t p = gyrocal::testing::Plateau(id, "run-seq", 0, 10);
        p.utime = Utime(now_s_);
        p.setpoint_c = setpoint_c;
        node_.bus().Publish(channels::Plateau(id), p);
        wire_.pace();
    }
    void PointOf(const std::string& id) {
        sensitivity_point_t s = gyrocal::testing::Sensitivity(id, "run-seq", 0, 10);
        s.utime = Utime(now_s_);
        node_.bus().Publish(channels::Sensitivity(id), s);
        wire_.pace();
    }
    SequencerNode& node() { return node_; }

    std::vector<run_event_t> events;
    std::vector<chamber_cmd_t> chamber;
    std::vector<turntable_cmd_t> turns;

private:
    SequencerNode node_;
    gyrocal::testing::Wire wire_;
    double now_s_ = 0.0;
    int64_t seq_ = 0;
};

TEST(SequencerNode, WalksTheProcedureOnDataTimeAndIgnoresWhatItDoesNotAwait) {
    MemqSequencer s;
    gyrocal::testing::StatusWatch status(s.node().bus(), "gyrocal-sequencer");
    // GIVEN two units on the bus: nothing before discover_s of data time
    s.AdvanceTo(1.5);
    EXPECT_TRUE(s.events.empty());
    // WHEN 2 s of data have passed THEN the run starts with both units and the first setpoint
    s.AdvanceTo(2.5);
    ASSERT_GE(s.events.size(), 2u);
    EXPECT_EQ(s.events[0].event, "start");
    EXPECT_EQ(s.events[0].sensor_ids, (std::vector<std::string>{"S01", "S02"}));
    ASSERT_EQ(s.chamber.size(), 1u);
    EXPECT_EQ(s.chamber[0].setpoint_c, 30.0);
    EXPECT_EQ(s.chamber[0].run_id, "run-seq");

    // A plateau of one unit, one of a unit not awaited, one of another setpoint: no turn yet
    s.AdvanceTo(60);
    s.PlateauOf("S01", 30.0);
    s.PlateauOf("S09", 30.0);
    s.PlateauOf("S02", 40.0);
    EXPECT_TRUE(s.turns.empty());
    // The second unit's plateau at this setpoint: the table turns +90
    s.PlateauOf("S02", 30.0);
    ASSERT_EQ(s.turns.size(), 1u);
    EXPECT_EQ(s.turns[0].move_deg, 90.0);
    // Both points of the +90 turn: the -90 turn
    s.AdvanceTo(70);
    s.PointOf("S01");
    s.PointOf("S01");  // a repeated answer counts once
    EXPECT_EQ(s.turns.size(), 1u);
    s.PointOf("S02");
    ASSERT_EQ(s.turns.size(), 2u);
    EXPECT_EQ(s.turns[1].move_deg, -90.0);
    // Both points of the -90 turn: the second setpoint
    s.AdvanceTo(80);
    s.PointOf("S01");
    s.PointOf("S02");
    ASSERT_EQ(s.chamber.size(), 2u);
    EXPECT_EQ(s.chamber[1].setpoint_c, 40.0);

    // A chamber fault is counted in STATUS (the run goes on: the plateau timeout decides)
    chamber_state_t fault = gyrocal::testing::Chamber(1);
    fault.utime = MemqSequencer::Utime(81);
    fault.fault = "compressor trip";
    s.node().bus().Publish(std::string(channels::kChamberState), fault);
    // The second setpoint's plateaus and turns: the run stops "completed"
    s.AdvanceTo(140);
    s.PlateauOf("S01", 40.0);
    s.PlateauOf("S02", 40.0);
    s.AdvanceTo(150);
    s.PointOf("S01");
    s.PointOf("S02");
    s.AdvanceTo(160);
    s.PointOf("S01");
    s.PointOf("S02");
    EXPECT_TRUE(s.node().done());
    ASSERT_FALSE(s.events.empty());
    EXPECT_EQ(s.events.back().event, "stop");
    EXPECT_NE(s.events.back().reason.find("completed"), std::string::npos)
        << s.events.back().reason;
    EXPECT_EQ(s.turns.size(), 4u);
    // Every order carries data time, never the wall clock
    for (const auto& c : s.chamber) EXPECT_LT(c.utime, MemqSequencer::Utime(200));
    for (const auto& t : s.turns) EXPECT_LT(t.utime, MemqSequencer::Utime(200));
    EXPECT_TRUE(gyrocal::testing::ForNode(s.node()).until([&] { return status.last.rejected >= 1; },
                                                          std::chrono::seconds(5)))
        << "rejected " << status.last.rejected << " last_reject " << status.last.last_reject;
    EXPECT_NE(status.last.last_reject.find("compressor trip"), std::string::npos)
        << status.last.last_reject;
}

}  // namespace
}  // namespace gyrocal::sequencer::node
