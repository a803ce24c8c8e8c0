// gyrocal-plateau's node in one process over memq:// (LCM's in-process provider): the scenario
// of plateau_scenario.hpp (plateaus with motion excluded, states, bad input counted), driven with
// bounded waits on conditions and no sleep; and no plateau while the temperature ramps. The real
// process over UDP: plateau_process_test.cpp.
#include "processors/plateau/node/plateau_node.hpp"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>
#include <string>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/lcmtypes/bus/wire.hpp"
#include "tests/lcmtypes/message_builders.hpp"
#include "tests/processors/plateau/plateau_scenario.hpp"

namespace gyrocal {
namespace {

// The node's options for the scenario (plateau_scenario.hpp), in-process over memq://.
plateau::node::PlateauOptions ScenarioOptions() {
    plateau::node::PlateauOptions o = plateau::node::PlateauOptions::Defaults();
    o.lcm_url = "memq://";
    testing::ApplyPlateauScenarioOptions(o);
    return o;
}

TEST(PlateauNode, PublishesPlateausAndCountsBadInput) {
    const plateau::node::PlateauOptions o = ScenarioOptions();
    ASSERT_EQ(o.Validate(), "");
    plateau::node::PlateauNode node(o);
    testing::StatusWatch status(node.bus(), "gyrocal-plateau");
    testing::PlateauScenario(node.bus(), testing::ForNode(node), status);
    EXPECT_EQ(node.plateaus_published(), 2);
}

// Known truth: S01's temperature ramps at 3 degC/min, above the 1 degC/min threshold by more than
// 20 standard errors of the window's slope (0.093 degC/min, plateau_scenario.hpp), so it is never
// stable; S02, flat at the same noise, is the control that the same data do give a plateau.
TEST(PlateauNode, NoPlateauWhileTheTemperatureRamps) {
    const plateau::node::PlateauOptions o = ScenarioOptions();
    ASSERT_EQ(o.Validate(), "");
    plateau::node::PlateauNode node(o);
    bus::Bus& bus = node.bus();
    std::map<std::string, int> plateaus;
    std::map<std::string, std::set<std::string>> states;
    int s01_heard = 0;  // subscribed after the node: when it has heard a sample, so has the node
    bus.Subscribe<plateau_t>(
        channels::AllSensors(channels::kPlateauPrefix),
        [&](const plateau_t& m, const std::string&) { ++plateaus[m.sensor_id]; });
    bus.Subscribe<plateau_state_t>(
        channels::AllSensors(channels::kStabilityPrefix),
        [&](const plateau_state_t& m, const std::string&) { states[m.sensor_id].insert(m.state); });
    bus.Subscribe<gyro_sample_t>(channels::Gyro("S01"),
                                 [&](const gyro_sample_t&, const std::string&) { ++s01_heard; });
    run_event_t start = testing::RunEvent("run-ramp", "start", {});
    start.utime = testing::kPlateauT0;
    bus.Publish(std::string(channels::kRunEvent), start);
    const testing::Wire wire = testing::ForNode(node);
    // 20 s at 100 Hz, the table at rest, the chamber at 30 degC; temperature noise 0.05 degC.
    const double sigma_t = 0.05, ramp_c_per_s = 3.0 / 60.0;
    std::mt19937_64 rng(23);
    std::normal_distribution<double> g(0, 1);
    for (int k = 1; k <= 2000; ++k) {
        const int64_t utime = testing::kPlateauT0 + k * 10'000;
        const double t = k * 0.01;
        if (k % 100 == 1) {
            chamber_state_t cs = testing::Chamber(k / 100);
            cs.utime = utime;
            cs.setpoint_c = cs.air_c = 30;
            bus.Publish(std::string(channels::kChamberState), cs);
        }
        bus.Publish(std::string(channels::kEncoder), testing::TableEncoder(utime, k, 0, 144000));
        for (const char* id : {"S01", "S02"}) {
            const double drift_c = std::string(id) == "S01" ? ramp_c_per_s * t : 0.0;
            gyro_sample_t s =
                testing::GyroSample(id, utime, k, 2.505, 30 + drift_c + sigma_t * g(rng));
            s.supply_v = 5.0;
            bus.Publish(channels::Gyro(id), s);
        }
        if (k % 20 == 0) wire.pace();
    }
    ASSERT_TRUE(wire.until([&] { return s01_heard == 2000 && plateaus["S02"] == 1; },
                           std::chrono::seconds(10)))
        << "S01 samples heard: " << s01_heard << ", S02 plateaus: " << plateaus["S02"];
    EXPECT_EQ(plateaus.count("S01"), 0u);
    EXPECT_EQ(states["S01"].count("averaging"), 0u);
    EXPECT_EQ(states["S01"].count("done"), 0u);
    EXPECT_EQ(node.plateaus_published(), 1);
}

}  // namespace
}  // namespace gyrocal
