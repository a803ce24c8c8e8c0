// gyrocal-rotation as a real OS process over UDP multicast (port 7741): the scenario of
// rotation_scenario.hpp through the process's own command line, then what only a process shows:
// its STATUS heartbeat over the network and a clean exit 0 on SIGTERM. The same scenario runs on
// the node in-process in rotation_node_test.cpp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/lcmtypes/bus/wire.hpp"
#include "tests/processors/rotation/rotation_scenario.hpp"

namespace gyrocal {
namespace {

constexpr const char* kUrl = "udpm://239.255.76.67:7741?ttl=0&recv_buf_size=4194304";

TEST(RotationProcess, PublishesOnePointPerMoveAndCountsBadInput) {
    bus::Bus bus(bus::BusOptions{kUrl});
    testing::StatusWatch status(bus, "gyrocal-rotation");
    const testing::Wire wire = testing::ForProcess(bus, "gyrocal-rotation");
    const auto dir = std::filesystem::temp_directory_path() /
                     ("gyrocal_rotation_mp_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    launch::ChildProcess child({GYROCAL_ROTATION_BIN, "--lcm-url", kUrl, "--sensors", "S01"},
                               (dir / "stdout.txt").string(), (dir / "stderr.txt").string());
    ASSERT_TRUE(wire.until([&] { return status.seen; }, std::chrono::seconds(10)))
        << "no STATUS from gyrocal-rotation";
    testing::RotationScenario(bus, wire, status);
    const launch::ExitStatus st = child.Stop();
    EXPECT_TRUE(st.exited && st.code == 0) << st.Describe();
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocal
