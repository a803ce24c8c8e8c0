// What the measured-data producers (gyrocal-csv-source, gyrocal-line-source, gyrocal-csv-record)
// share, with real processes: bad options and configuration are refused with exit code 2 and one
// line naming the option and what is valid, before touching the bus; --help lists the options and
// exit codes; SIGTERM leaves through the normal path (exit 0).
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <string>

#include "tests/producers/producer_process_support.hpp"
#include "tests/support/wait/wait_until.hpp"

namespace gyrocal::test {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

struct BadCase {
    std::vector<std::string> argv;
    std::string expected;  // in stderr
};

TEST(SourcesBadInput, BadOptionsExitTwoNamingTheOption) {
    Scratch dir("bad_options");
    WriteSyntheticCsv(dir.Path("in.csv"), SyntheticSpec{{"S01"}, 10.0, 1.0, 1});
    const std::string in = dir.Path("in.csv");
    const std::string src = Bin("gyrocal-csv-source");
    const std::string line = Bin("gyrocal-line-source");
    const std::string rec = Bin("gyrocal-csv-record");
    const std::vector<BadCase> cases = {
        {{src, in, "--speed", "0"}, "--speed 0 is out of range; valid: > 0"},
        {{src, in, "--speed", "-2"}, "--speed -2 is out of range"},
        {{src, in, "--speed", "fast"}, "--speed"},
        {{src, dir.Path("missing.csv")},
         "--file '" + dir.Path("missing.csv") + "' cannot be opened"},
        {{src}, "file is required"},
        {{src, in, "--preset", "612"}, "--preset '612' is unknown; valid: 610 or 613"},
        {{src, in, "--on-error", "ignore"}, "--on-error 'ignore' is unknown; valid: stop or skip"},
        {{src, in, "--temp-v-per-c", "0"}, "--temp-v-per-c 0 is out of range"},
        // The old name sets the same value (hidden from --help); both at once are refused.
        {{src, in, "--temp-v-per-k", "0"}, "--temp-v-per-c 0 is out of range"},
        {{line, "--temp-v-per-k", "0"}, "--temp-v-per-c 0 is out of range"},
        {{src, in, "--temp-v-per-c", "0.01", "--temp-v-per-k", "0.01"},
         "--temp-v-per-k is the old name of --temp-v-per-c: give one of them"},
        {{src, in, "--encoder-counts-per-rev", "0"}, "--encoder-counts-per-rev 0 is out of range"},
        {{src, in, "--max-rate-hz", "0", "--max"}, "--max-rate-hz 0 is out of range"},
        {{src, in, "--max", "--speed", "2"}, "--max"},
        {{line, "--time", "gps"}, "--time 'gps' is unknown; valid: stream or wall"},
        {{line, "--preset", "x"}, "--preset 'x' is unknown"},
        {{line, "--device", dir.Path("no-such-tty")},
         "--device '" + dir.Path("no-such-tty") + "' cannot be opened"},
        {{rec}, "--out is required"},
        {{rec, "--out", dir.Path("no/such/dir/out.csv")},
         "--out '" + dir.Path("no/such/dir/out.csv") + "' cannot be created"},
        {{rec, "--out", dir.Path("o.csv"), "--sensors", "S01,S 2"},
         "--sensors: 'S 2' is not a valid sensor id"},
        {{rec, "--out", dir.Path("o.csv"), "--idle-exit-s", "-1"},
         "--idle-exit-s -1 is out of range"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        const BadCase& c = cases[i];
        std::string cmd;
        for (const auto& a : c.argv) cmd += a + " ";
        SCOPED_TRACE(cmd);
        const std::string err = dir.Path("err" + std::to_string(i));
        launch::ChildProcess p(c.argv, "", err);
        const launch::ExitStatus s = WaitExit(p, 10s);
        EXPECT_TRUE(s.exited) << s.Describe();
        EXPECT_EQ(s.code, 2);
        EXPECT_THAT(Slurp(err), HasSubstr(c.expected));
    }
}

TEST(SourcesBadInput, HelpListsOptionsAndExitCodes) {
    Scratch dir("help");
    for (const std::string exe :
         {"gyrocal-csv-source", "gyrocal-line-source", "gyrocal-csv-record"}) {
        launch::ChildProcess p({Bin(exe), "--help"}, dir.Path(exe + ".out"), "");
        EXPECT_EQ(WaitExit(p, 10s).code, 0);
        const std::string help = Slurp(dir.Path(exe + ".out"));
        EXPECT_THAT(help, HasSubstr("--lcm-url"));
        EXPECT_THAT(help, HasSubstr("Exit codes: 0"));
    }
}

// Whether process `pid` has a handler for SIGTERM (its SigCgt mask in /proc/<pid>/status).
bool CatchesSigterm(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);) {
        if (line.rfind("SigCgt:", 0) == 0)
            return (std::stoull(line.substr(7), nullptr, 16) >> (SIGTERM - 1)) & 1u;
    }
    return false;
}

TEST(SourcesSignals, SigtermStopsBothSourcesWithExitZero) {
    // GIVEN a 3 s file replayed in real time, and a line source waiting on an idle FIFO
    Scratch dir("signals");
    WriteSyntheticCsv(dir.Path("in.csv"), SyntheticSpec{});
    const std::string fifo = dir.Path("idle.fifo");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    launch::ChildProcess src(
        {Bin("gyrocal-csv-source"), dir.Path("in.csv"), "--lcm-url", "memq://"}, "",
        dir.Path("src.err"));
    launch::ChildProcess line(
        {Bin("gyrocal-line-source"), "--device", fifo, "--lcm-url", "memq://"}, "",
        dir.Path("line.err"));
    const int fd = open(fifo.c_str(), O_WRONLY);  // returns once the source has opened it
    ASSERT_GE(fd, 0);
    // Both have installed their SIGTERM handlers (the line source did before opening the FIFO).
    ASSERT_TRUE(testing::WaitUntil([&] { return CatchesSigterm(src.pid()); }, 10s))
        << Slurp(dir.Path("src.err"));
    ASSERT_TRUE(CatchesSigterm(line.pid()));
    // WHEN both get SIGTERM mid-way
    src.Signal(SIGTERM);
    line.Signal(SIGTERM);
    // THEN both leave through their normal path: exit 0 with a summary
    const launch::ExitStatus s = WaitExit(src, 5s);
    EXPECT_TRUE(s.exited && s.code == 0) << s.Describe();
    EXPECT_THAT(Slurp(dir.Path("src.err")), HasSubstr("; stopped by signal"));
    const launch::ExitStatus l = WaitExit(line, 5s);
    EXPECT_TRUE(l.exited && l.code == 0) << l.Describe();
    EXPECT_THAT(Slurp(dir.Path("line.err")), HasSubstr("published 0 rows from " + fifo));
    close(fd);
}

}  // namespace
}  // namespace gyrocal::test
