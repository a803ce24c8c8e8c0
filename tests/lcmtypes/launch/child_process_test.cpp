// Child processes as the launcher and the end-to-end tests use them.
#include "lcmtypes/launch/child_process.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/support/wait/wait_until.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;

TEST(ChildProcess, ReportsExitCodeAndOutput) {
    const std::string out = ::testing::TempDir() + "child_out.txt";
    launch::ChildProcess c({"sh", "-c", "echo hello; exit 7"}, out, out);
    auto s = c.Wait(10s);
    ASSERT_TRUE(s.has_value());
    EXPECT_TRUE(s->exited);
    EXPECT_EQ(s->code, 7);
    std::ifstream f(out);
    std::string line;
    std::getline(f, line);
    EXPECT_EQ(line, "hello");
}

TEST(ChildProcess, MissingProgramIsAnErrorWithTheReason) {
    try {
        launch::ChildProcess c({"/nonexistent/gyrocal-nothing"});
        FAIL() << "expected an exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("gyrocal-nothing"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos) << e.what();
    }
}

TEST(ChildProcess, RunsInItsWorkingDirectoryAndWaitBlocksUntilTheEnd) {
    // GIVEN a fresh directory; WHEN a shell started there prints its directory and exits 3
    const std::filesystem::path dir =
        std::filesystem::path(::testing::TempDir()) / "child_working_dir";
    std::filesystem::create_directories(dir);
    const std::string out = (dir / "pwd.txt").string();
    const launch::ExitStatus s =
        launch::ChildProcess({"sh", "-c", "pwd -P; sleep 0.2; exit 3"},
                             launch::ChildOptions{out, out, dir.string(), {}})
            .Wait();
    // THEN the blocking Wait reports its exit and it ran in that directory
    EXPECT_TRUE(s.exited);
    EXPECT_EQ(s.code, 3);
    EXPECT_EQ(launch::ReadLog(out), std::filesystem::canonical(dir).string() + "\n");
}

TEST(ChildProcess, AWorkingDirectoryThatCannotBeEnteredIsAnErrorWithTheReason) {
    try {
        launch::ChildProcess c({"sh", "-c", "exit 0"},
                               launch::ChildOptions{"", "", "/nonexistent/gyrocal-dir", {}});
        FAIL() << "expected an exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/gyrocal-dir"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos) << e.what();
    }
}

TEST(ChildProcess, PassesTheGivenFdsAsThreeFourAndNoOtherFd) {
    // GIVEN two pipes, their ends passed as the child's fds 3 and 4, and a third pipe not passed
    int in[2], out[2], other[2];
    ASSERT_EQ(::pipe(in), 0);
    ASSERT_EQ(::pipe(out), 0);
    ASSERT_EQ(::pipe(other), 0);
    ASSERT_EQ(::write(in[1], "ping\n", 5), 5);
    ::close(in[1]);
    launch::ChildOptions o;
    o.child_fds = {in[0], out[1]};
    // WHEN the child copies fd 3 to fd 4 and reports whether the other pipe's fd is open
    const std::string probe = "cat <&3 >&4; if [ -e /proc/self/fd/" + std::to_string(other[1]) +
                              " ]; then echo open >&4; else echo closed >&4; fi";
    const launch::ExitStatus s = launch::ChildProcess({"sh", "-c", probe}, o).Wait();
    ::close(in[0]);
    ::close(out[1]);
    std::string got(64, '\0');
    got.resize(static_cast<size_t>(std::max<ssize_t>(0, ::read(out[0], got.data(), got.size()))));
    ::close(out[0]);
    ::close(other[0]);
    ::close(other[1]);
    // THEN it read fd 3, wrote fd 4, and held no other fd of the parent's
    EXPECT_TRUE(s.exited && s.code == 0) << s.Describe();
    EXPECT_EQ(got, "ping\nclosed\n");
}

TEST(FindOnPath, FindsWhatExecvpWouldStartAndNothingElse) {
    const std::string sh = launch::FindOnPath("sh");
    ASSERT_FALSE(sh.empty());
    EXPECT_EQ(sh.substr(sh.size() - 3), "/sh");
    EXPECT_EQ(launch::FindOnPath(sh), sh);  // a path is taken as it is
    EXPECT_EQ(launch::FindOnPath("gyrocal-no-such-program"), "");
    EXPECT_EQ(launch::FindOnPath("/nonexistent/sh"), "");
}

TEST(ChildProcess, StopEscalatesToSigkillAndReachesGrandchildren) {
    // The shell ignores SIGTERM and runs a grandchild; Stop() must still end both.
    const std::string pidfile = ::testing::TempDir() + "grandchild.pid";
    std::filesystem::remove(pidfile);
    launch::ChildProcess c(
        {"sh", "-c", "trap '' TERM; sleep 60 & echo $! > " + pidfile + "; wait"});
    // The shell writes the grandchild's pid after it has set the trap: once it is there, both
    // are in place.
    pid_t grandchild = 0;
    ASSERT_TRUE(testing::WaitUntil(
        [&] {
            std::ifstream f(pidfile);
            return static_cast<bool>(f >> grandchild) && grandchild > 0;
        },
        10s))
        << "the shell never wrote " << pidfile;
    launch::ExitStatus s = c.Stop(500ms);
    EXPECT_FALSE(s.exited);
    EXPECT_EQ(s.signal, SIGKILL);
    // The grandchild goes (it may linger as a zombie of init briefly).
    std::string content;
    EXPECT_TRUE(testing::WaitUntil(
        [&] {
            std::ifstream stat("/proc/" + std::to_string(grandchild) + "/stat");
            content.assign(std::istreambuf_iterator<char>(stat), std::istreambuf_iterator<char>());
            return content.empty() || content.find(") Z") != std::string::npos;
        },
        10s))
        << content;
}

}  // namespace
}  // namespace gyrocal
