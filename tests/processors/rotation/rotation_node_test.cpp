// gyrocal-rotation's node in one process over memq:// (LCM's in-process provider): the scenario
// of rotation_scenario.hpp (a point per move within the noise of the truth, bad input counted),
// driven with bounded waits on conditions and no sleep. The real process over UDP:
// rotation_process_test.cpp.
#include "processors/rotation/node/rotation_node.hpp"

#include <gtest/gtest.h>

#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/lcmtypes/bus/wire.hpp"
#include "tests/processors/rotation/rotation_scenario.hpp"

namespace gyrocal {
namespace {

TEST(RotationNode, PublishesOnePointPerMoveAndCountsBadInput) {
    rotation::node::RotationOptions o = rotation::node::RotationOptions::Defaults();
    o.lcm_url = "memq://";
    o.sensors = testing::kRotationScenarioSensors;
    ASSERT_EQ(o.Validate(), "");
    rotation::node::RotationNode node(o);
    testing::StatusWatch status(node.bus(), "gyrocal-rotation");
    testing::RotationScenario(node.bus(), testing::ForNode(node), status);
}

}  // namespace
}  // namespace gyrocal
