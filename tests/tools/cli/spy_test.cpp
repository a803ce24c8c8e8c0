// lcm-spy smoke test: under a virtual X display, `gyrocal spy` starts lcm.spy.Spy (which Debian's
// launcher cannot, because of -Xincgc on Java 17) and it finds every gyrocal type in the jar.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "lcmtypes/launch/child_process.hpp"
#include "tests/support/wait/wait_until.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;

int CountLcmFiles() {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(GYROCAL_LCMTYPES_DIR))
        n += e.path().extension() == ".lcm" ? 1 : 0;
    return n;
}

TEST(Spy, StartsUnderXvfbAndFindsEveryProjectType) {
    if (!std::filesystem::exists("/usr/bin/xvfb-run"))
        GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb xauth); no display to "
                        "start lcm-spy on";
    const std::string log = ::testing::TempDir() + "spy.log";
    launch::ChildProcess spy(
        {"xvfb-run", "-a", GYROCAL_CLI, "spy", "--lcm-url", "udpm://239.255.76.67:7706?ttl=0"}, log,
        log);
    const std::string expected = "Found " + std::to_string(CountLcmFiles()) + " LCM types";
    std::string out;
    bool ended = false;
    testing::WaitUntil(
        [&] {
            out = launch::ReadLog(log);
            ended = spy.Poll().has_value();
            return ended || out.find(expected) != std::string::npos;
        },
        30s, 100ms);
    ASSERT_FALSE(ended) << "lcm-spy ended early:\n" << out;
    EXPECT_NE(out.find(expected), std::string::npos) << out;
    // Still running a moment later: the window is up, not an exception at start. Time itself:
    // what is tested is that it stays up for a second.
    std::this_thread::sleep_for(1s);
    EXPECT_FALSE(spy.Poll().has_value()) << launch::ReadLog(log);
    EXPECT_EQ(launch::ReadLog(log).find("Exception"), std::string::npos) << launch::ReadLog(log);
}

TEST(Spy, MissingTypesJarIsAClearError) {
    const std::string log = ::testing::TempDir() + "spy_nojar.log";
    launch::ChildProcess spy(
        {"env", "GYROCAL_TYPES_JAR=/nonexistent/types.jar", GYROCAL_CLI, "spy"}, log, log);
    auto s = spy.Wait(10s);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->code, 1);
    EXPECT_NE(launch::ReadLog(log).find("/nonexistent/types.jar"), std::string::npos)
        << launch::ReadLog(log);
}

}  // namespace
}  // namespace gyrocal
