// gyrocal-plateau as a real OS process over UDP multicast (port 7740): the scenario of
// plateau_scenario.hpp through the process's own command line, then what only a process shows:
// its STATUS heartbeat over the network and a clean exit 0 on SIGTERM. The same scenario runs on
// the node in-process in plateau_node_test.cpp.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/lcmtypes/bus/process_scenario.hpp"
#include "tests/processors/plateau/plateau_scenario.hpp"

namespace gyrocal {
namespace {

constexpr const char* kUrl = "udpm://239.255.76.67:7740?ttl=0&recv_buf_size=4194304";

TEST(PlateauProcess, PublishesPlateausAndCountsBadInput) {
    std::vector<std::string> argv = {GYROCAL_PLATEAU_BIN, "--lcm-url", kUrl};
    argv.insert(argv.end(), testing::kPlateauScenarioFlags.begin(),
                testing::kPlateauScenarioFlags.end());
    testing::RunScenarioOnProcess(kUrl, "gyrocal-plateau", argv, testing::PlateauScenario);
}

}  // namespace
}  // namespace gyrocal
