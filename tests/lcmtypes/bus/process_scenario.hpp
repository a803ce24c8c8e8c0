#pragma once
// A node's scenario (a function of the test's bus, the wire to the process and its STATUS)
// through the real process: started with `argv` (its --lcm-url the test's `url`), the scenario
// run once its first STATUS is heard (within 10 s), then SIGTERM and a clean exit 0 expected.
// Its stdout and stderr go to a scratch folder, removed afterwards. The processors' process tests
// share it; their nodes run the same scenario in-process through ForNode (wire.hpp).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/lcmtypes/bus/wire.hpp"

namespace gyrocal::testing {

// `process`: the STATUS name of the process, also its scratch folder's.
template <class Scenario>
void RunScenarioOnProcess(const std::string& url, const std::string& process,
                          const std::vector<std::string>& argv, Scenario scenario) {
    bus::Bus bus(bus::BusOptions{url});
    StatusWatch status(bus, process);
    const Wire wire = ForProcess(bus, process);
    const auto dir =
        std::filesystem::temp_directory_path() / (process + "_mp_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    launch::ChildProcess child(argv, (dir / "stdout.txt").string(), (dir / "stderr.txt").string());
    ASSERT_TRUE(wire.until([&] { return status.seen; }, std::chrono::seconds(10)))
        << "no STATUS from " << process;
    scenario(bus, wire, status);
    const launch::ExitStatus st = child.Stop();
    EXPECT_TRUE(st.exited && st.code == 0) << st.Describe();
    std::filesystem::remove_all(dir);
}

}  // namespace gyrocal::testing
