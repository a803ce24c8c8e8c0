// What calibrate surfaces of a failed child: its own error lines (the one shape every process
// writes, lcmtypes/process/process_main.hpp), else the last line of its log.
#include "tools/supervisor/child_errors.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "lcmtypes/process/process_main.hpp"

namespace gyrocal::supervisor {
namespace {

using ::testing::ElementsAre;

TEST(ChildErrors, TheProcessesOwnErrorLinesWithoutTheirPrefix) {
    const std::string log =
        "gyrocal-csv-source: warning: f.csv: ignoring unknown column(s) x\n" +
        process::ErrorLine("gyrocal-csv-source", "f.csv:12: column temp_v: 'abc'") +
        "\ngyrocal-csv-source: nothing published\n";
    EXPECT_THAT(ErrorLinesOf(log, "gyrocal-csv-source"),
                ElementsAre("f.csv:12: column temp_v: 'abc'"));
}

TEST(ChildErrors, AnotherProcessesErrorLineIsNotThisOnes) {
    // A line of another program in the same log (a library's message) is not this child's error.
    const std::string log = process::ErrorLine("lcm", "boom") + "\nlast words\n";
    EXPECT_THAT(ErrorLinesOf(log, "gyrocal-plateau"),
                ElementsAre("last line of its log: last words"));
}

TEST(ChildErrors, OnlyTheLastFewAreKeptOldestFirst) {
    std::string log;
    for (int i = 1; i <= 5; ++i) log += process::ErrorLine("p", "e" + std::to_string(i)) + "\r\n";
    EXPECT_THAT(ErrorLinesOf(log, "p", 2), ElementsAre("e4", "e5"));
}

TEST(ChildErrors, AnEmptyLogSaysNothing) {
    EXPECT_TRUE(ErrorLinesOf("", "p").empty());
    EXPECT_TRUE(ErrorLinesOf("\n  \n", "p").empty());
}

TEST(ChildErrors, TheCauseFollowsWhatHappened) {
    EXPECT_EQ(WithCause("csv source exit code 1", {"a", "b"}),
              "csv source exit code 1; it said: a | b");
    EXPECT_EQ(WithCause("x", {}), "x");
}

}  // namespace
}  // namespace gyrocal::supervisor
