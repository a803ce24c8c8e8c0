// gyrocal-sim-rig's node in one process over memq:// (LCM's in-process provider): commands
// published on the node's own bus before it runs 6 s of simulated time at 100x. Known truth: the
// table ordered +90 deg (30 deg/s by default: done in about 3.5 s) ends 90 deg from where it
// started within one encoder count; the samples of each unit are contiguous, 10 ms of simulated
// time apart (100 Hz), 6 s of them; the impossible chamber order is refused and said in the
// fault of the CHAMBER_STATE after it. No sleep: Run() returns at --duration-s and what it
// published last is handled after. The real process (STATUS, the built-in profile, determinism, bad
// options): sim_rig_process_test.cpp.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "producers/sim_rig/rig_node.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/producers/sim_rig/rig_orders.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;

TEST(SimRigNode, ObeysATurnRefusesAnImpossibleOrderAndPublishesContiguousSamples) {
    sim_rig::SimRigOptions o = sim_rig::SimRigOptions::Defaults();
    o.lcm_url = "memq://";
    o.speed = 100;
    o.duration_s = 6;
    o.rig.num_units = 2;
    o.rig.seed = 11;
    sim_rig::SimRigNode node(o);
    bus::Bus& bus = node.bus();
    std::map<std::string, std::vector<gyro_sample_t>> gyro;
    std::vector<encoder_sample_t> encoder;
    std::vector<chamber_state_t> chamber;
    bus.Subscribe<gyro_sample_t>(
        channels::AllSensors(channels::kGyroPrefix),
        [&](const gyro_sample_t& m, const std::string&) { gyro[m.sensor_id].push_back(m); });
    testing::CollectInto(bus, std::string(channels::kEncoder), encoder);
    testing::CollectInto(bus, std::string(channels::kChamberState), chamber);
    // GIVEN a +90 deg turn, then an impossible chamber order (200 degC, outside -45..90); the
    // fault field says the last order's refusal (an accepted order clears it)
    bus.Publish(std::string(channels::kTurntableCmd), testing::QuarterTurn());
    bus.Publish(std::string(channels::kChamberCmd), testing::ImpossibleChamberOrder());
    // WHEN the rig runs 6 s of simulated time
    EXPECT_EQ(node.Run(), 0);
    ASSERT_TRUE(testing::HandleUntil(
        bus, [&] { return !bus.Handle(0ms); }, 10'000ms, 0ms));
    // THEN the table has turned 90 deg within one count
    ASSERT_FALSE(encoder.empty());
    const double count_deg = 360.0 / encoder.back().counts_per_rev;
    EXPECT_NEAR(encoder.back().angle_deg - encoder.front().angle_deg, 90.0, count_deg + 1e-9);
    for (size_t i = 1; i < encoder.size(); ++i)
        ASSERT_EQ(encoder[i].seq, encoder[i - 1].seq + 1) << "encoder seq gap at " << i;
    // and each unit's samples are contiguous at 100 Hz of simulated time: 600 in 6 s (one more
    // or less, as the first and last instants fall)
    ASSERT_EQ(gyro.size(), 2u);
    for (const auto& [id, samples] : gyro) {
        SCOPED_TRACE(id);
        EXPECT_NEAR(static_cast<double>(samples.size()), 600.0, 1.0);
        for (size_t i = 1; i < samples.size(); ++i) {
            ASSERT_EQ(samples[i].seq, samples[i - 1].seq + 1) << "seq gap at " << i;
            ASSERT_EQ(samples[i].utime - samples[i - 1].utime, 10'000) << "at " << i;
        }
    }
    // and the impossible order was refused: the chamber states after it say why (the one at
    // t = 0 may come before the order is served), none took it
    ASSERT_GE(chamber.size(), 2u);
    EXPECT_NE(chamber.back().fault.find("outside the chamber's range"), std::string::npos)
        << chamber.back().fault;
    for (const chamber_state_t& c : chamber) {
        EXPECT_NE(c.cmd_id, 6);
        EXPECT_NE(c.setpoint_c, 200.0);
    }
}

}  // namespace
}  // namespace gyrocal
