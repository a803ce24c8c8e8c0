// gyrocal-plateau's node in one process over memq:// (LCM's in-process provider): the scenario
// of plateau_scenario.hpp (plateaus with motion excluded, states, bad input counted), driven with
// bounded waits on conditions and no sleep. The real process over UDP: plateau_process_test.cpp.
#include "plateau_node.hpp"

#include <gtest/gtest.h>

#include "plateau_scenario.hpp"
#include "status_watch.hpp"
#include "wire.hpp"

namespace gyrocal {
namespace {

TEST(PlateauNode, PublishesPlateausAndCountsBadInput) {
    PlateauOptions o = PlateauOptions::Defaults();
    o.lcm_url = "memq://";
    testing::ApplyPlateauScenarioOptions(o);
    ASSERT_EQ(o.Validate(), "");
    PlateauNode node(o);
    testing::StatusWatch status(node.bus(), "gyrocal-plateau");
    testing::PlateauScenario(node.bus(), testing::ForNode(node), status);
    EXPECT_EQ(node.plateaus_published(), 2);
}

}  // namespace
}  // namespace gyrocal
