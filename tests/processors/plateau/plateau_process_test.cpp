// gyrocal-plateau as a real OS process over UDP multicast (port 7740): the scenario of
// plateau_scenario.hpp through the process's own command line, then what only a process shows:
// its STATUS heartbeat over the network and a clean exit 0 on SIGTERM. The same scenario runs on
// the node in-process in plateau_node_test.cpp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/lcmtypes/bus/wire.hpp"
#include "tests/processors/plateau/plateau_scenario.hpp"

namespace gyrocal {
namespace {

constexpr const char* kUrl = "udpm://239.255.76.67:7740?ttl=0&recv_buf_size=4194304";

TEST(PlateauProcess, PublishesPlateausAndCountsBadInput) {
    bus::Bus bus(bus::BusOptions{kUrl});
    testing::StatusWatch status(bus, "gyrocal-plateau");
    const testing::Wire wire = testing::ForProcess(bus, "gyrocal-plateau");
    const auto dir =
        std::filesystem::temp_directory_path() / ("gyrocal_plateau_mp_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    std::vector<std::string> argv = {GYROCAL_PLATEAU_BIN, "--lcm-url", kUrl};
    argv.insert(argv.end(), testing::kPlateauScenarioFlags.begin(),
                testing::kPlateauScenarioFlags.end());
    launch::ChildProcess child(argv, (dir / "stdout.txt").string(), (dir / "stderr.txt").string());
    ASSERT_TRUE(wire.until([&] { return status.seen; }, std::chrono::seconds(10)))
        << "no STATUS from gyrocal-plateau";
    testing::PlateauScenario(bus, wire, status);
    const launch::ExitStatus st = child.Stop();
    EXPECT_TRUE(st.exited && st.code == 0) << st.Describe();
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocal
