// gyrocal-rotation as a real OS process over UDP multicast (port 7741): the scenario of
// rotation_scenario.hpp through the process's own command line, then what only a process shows:
// its STATUS heartbeat over the network and a clean exit 0 on SIGTERM. The same scenario runs on
// the node in-process in rotation_node_test.cpp.
#include <gtest/gtest.h>

#include "tests/lcmtypes/bus/process_scenario.hpp"
#include "tests/processors/rotation/rotation_scenario.hpp"

namespace gyrocal {
namespace {

constexpr const char* kUrl = "udpm://239.255.76.67:7741?ttl=0&recv_buf_size=4194304";

TEST(RotationProcess, PublishesOnePointPerMoveAndCountsBadInput) {
    testing::RunScenarioOnProcess(kUrl, "gyrocal-rotation",
                                  {GYROCAL_ROTATION_BIN, "--lcm-url", kUrl, "--sensors", "S01"},
                                  testing::RotationScenario);
}

}  // namespace
}  // namespace gyrocal
