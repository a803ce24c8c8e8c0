// gyrocal-sequencer's options, as a process: every bad option exits 2 with one line that names the
// process and the option, before anything is published; --help exits 0 and lists the exit codes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "lcmtypes/launch/child_process.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;

struct Case {
    std::vector<std::string> args;
    std::string says;  // the stderr line must contain this
};

TEST(SequencerCli, BadOptionsExitTwoNamingTheOption) {
    const std::string err =
        ::testing::TempDir() + "gyrocal_seq_cli_" + std::to_string(getpid()) + ".err";
    const std::vector<Case> cases = {
        {{"--profile", "seven"}, "--profile: unknown profile 'seven'"},
        {{"--sensors", "S01,bad id!"}, "--sensors: 'bad id!' is not a valid sensor id"},
        {{"--ramp-rate-c-per-min", "0"}, "ramp"},
        {{"--setpoints-c", "20,abc"}, "--setpoints-c"},
        {{"--run-config-json", "{\"a\":"}, "--run-config-json: is not valid JSON"},
        {{"--bogus"}, "--bogus"},
        {{"--resume-setpoint-index", "1"},
         "--resume-setpoint-index: resuming needs the run's --run-id and --sensors"},
        {{"--run-id", "R", "--sensors", "A", "--resume-setpoint-index", "6"},
         "--resume-setpoint-index: resume setpoint index 6: valid is 0..5"},  // default profile:
                                                                              // six
        {{"--move-attempts", "0"}, "--move-attempts: move attempts 0: valid is 1..5"},
        {{"--profile", "ramp", "--turn-interval-s", "1"}, "--turn-interval-s: turn interval 1 s"},
        {{"--profile", "ramp", "--dwell-s", "-5"}, "--dwell-s: dwell -5 s"},
        {{"--profile", "ramp", "--ramp-range-c", "40,10"},
         "--ramp-range-c: MIN,MAX needs MIN < MAX"},
        {{"--profile", "five", "--ramp-range-c", "10,40"},
         "--ramp-range-c: only with --profile ramp"},
        {{"--profile", "five", "--target-offset-dps", "0.1"}, "only with --profile ramp"},
        {{"--profile", "ramp", "--target-sensitivity-pct", "150"}, "--target-sensitivity-pct"},
    };
    for (const Case& c : cases) {
        std::vector<std::string> argv = {GYROCAL_SEQUENCER_EXE, "--lcm-url", "memq://"};
        argv.insert(argv.end(), c.args.begin(), c.args.end());
        launch::ChildProcess p(argv, "/dev/null", err);
        const auto st = p.Wait(10s);
        ASSERT_TRUE(st.has_value()) << c.args[0] << ": did not exit";
        EXPECT_TRUE(st->exited && st->code == 2) << c.args[0] << ": " << st->Describe();
        const std::string said = launch::ReadLog(err);
        EXPECT_EQ(said.rfind("gyrocal-sequencer: error: ", 0), 0u) << said;
        EXPECT_NE(said.find(c.says), std::string::npos) << said;
    }
    std::filesystem::remove(err);
}

TEST(SequencerCli, HelpExitsZeroWithTheExitCodes) {
    const std::string out =
        ::testing::TempDir() + "gyrocal_seq_help_" + std::to_string(getpid()) + ".out";
    launch::ChildProcess p({GYROCAL_SEQUENCER_EXE, "--help"}, out, "/dev/null");
    const auto st = p.Wait(10s);
    ASSERT_TRUE(st.has_value());
    EXPECT_TRUE(st->exited && st->code == 0) << st->Describe();
    const std::string help = launch::ReadLog(out);
    EXPECT_NE(help.find("3 run aborted"), std::string::npos) << help;
    EXPECT_NE(help.find("--sensors"), std::string::npos) << help;
    std::filesystem::remove(out);
}

}  // namespace
}  // namespace gyrocal
