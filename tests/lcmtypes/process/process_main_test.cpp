// The frame of every process's main(): the exit code and the message of each way a command line
// can end, and of a node that returns or throws.
#include "lcmtypes/process/process_main.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace gyrocal {
namespace {

struct Case {
    std::vector<std::string> args;  // after the program name
    std::string validation_error;   // what the process's own check says ("": valid)
    std::optional<int> exit_code;   // nullopt: the process goes on
    std::string says;  // on stderr, one line after "gyrocal-test: error: " ("": nothing)
    std::string ends;  // how that line ends
};

TEST(ParseCommandLine, HelpBadOptionsAndFailedChecksEndTheProcessWithTheirCode) {
    const std::vector<Case> cases = {
        {{"--count", "3"}, "", std::nullopt, "", ""},
        {{"--help"}, "", 0, "", ""},
        // CLI11's own messages name the option or value; the frame adds where to look.
        {{"--bogus"}, "", 2, "--bogus", " (see --help)\n"},
        {{"--count", "x"}, "", 2, "x", " (see --help)\n"},
        {{"--count", "0"},
         "--count 0 is out of range; valid: > 0",
         2,
         "--count 0 is out of range; valid: > 0",
         "\n"},
    };
    for (const Case& c : cases) {
        std::string line;
        for (const auto& a : c.args) line += a + " ";
        SCOPED_TRACE(line);
        CLI::App app{"a test process"};
        int count = 1;
        app.add_option("--count", count, "how many");
        std::vector<std::string> words = {"gyrocal-test"};
        words.insert(words.end(), c.args.begin(), c.args.end());
        std::vector<char*> argv;
        for (std::string& w : words) argv.push_back(w.data());
        ::testing::internal::CaptureStdout();
        ::testing::internal::CaptureStderr();
        const std::optional<int> code =
            process::ParseCommandLine(app, static_cast<int>(argv.size()), argv.data(),
                                      "gyrocal-test", [&c] { return c.validation_error; });
        const std::string out = ::testing::internal::GetCapturedStdout();
        EXPECT_EQ(code, c.exit_code);
        const std::string err = ::testing::internal::GetCapturedStderr();
        if (c.says.empty()) {
            EXPECT_EQ(err, "");
        } else {
            EXPECT_EQ(err.rfind("gyrocal-test: error: ", 0), 0u) << err;
            EXPECT_NE(err.find(c.says), std::string::npos) << err;
            ASSERT_GE(err.size(), c.ends.size());
            EXPECT_EQ(err.substr(err.size() - c.ends.size()), c.ends) << err;
            EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
        }
        if (c.args == std::vector<std::string>{"--help"}) {
            EXPECT_NE(out.find("--count"), std::string::npos) << out;
        }
        if (!c.exit_code) {
            EXPECT_EQ(count, 3);
        }
    }
}

TEST(RunUntilStopped, ZeroWhenTheNodeReturnsOneNamingTheProcessWhenItThrows) {
    bool ran = false;
    EXPECT_EQ(process::RunUntilStopped("gyrocal-test", [&ran] { ran = true; }), 0);
    EXPECT_TRUE(ran);
    ::testing::internal::CaptureStderr();
    EXPECT_EQ(process::RunUntilStopped("gyrocal-test",
                                       [] { throw std::runtime_error("LCM cannot open"); }),
              1);
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "gyrocal-test: error: LCM cannot open\n");
}

TEST(ErrorLine, OneShapeAndItsRecognition) {
    EXPECT_EQ(process::ErrorLine("gyrocal-x", "f.csv:3: column a: bad; valid: b"),
              "gyrocal-x: error: f.csv:3: column a: bad; valid: b");
    EXPECT_TRUE(process::IsErrorLineOf("gyrocal-x", process::ErrorLine("gyrocal-x", "w")));
    EXPECT_FALSE(process::IsErrorLineOf("gyrocal-x", process::ErrorLine("gyrocal-xy", "w")));
    EXPECT_FALSE(process::IsErrorLineOf("gyrocal-x", "gyrocal-x: warning: w"));
}

}  // namespace
}  // namespace gyrocal
