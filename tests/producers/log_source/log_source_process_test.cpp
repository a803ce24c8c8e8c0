// gyrocal-log-source with real processes (port 7738): a log of batched gyro samples (and the
// recorded run's flow marks, which are not replayed) published --max to a gyrocal-csv-record,
// which answers the flow marks and writes every sample it gets: every sample arrives, in order;
// a damaged log publishes nothing and names the byte.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "tests/lcmtypes/message_builders.hpp"
#include "tests/producers/log_source/log_writer.hpp"
#include "tests/producers/producer_process_support.hpp"

namespace gyrocal::test {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

// 50 batches of 16 samples of unit L1 (seq 0..799) with a stale flow mark among them.
void WriteLog(const std::string& path, bool damaged) {
    std::ofstream out(path, std::ios::binary);
    int64_t n = 0;
    for (int b = 0; b < 50; ++b) {
        WriteEvent(out, n++, 1000 + b, "GYRO_L1",
                   testing::EncodeMsg(testing::GyroBatch("L1", 16 * b, 16)));
        if (b == 10)
            WriteEvent(out, n++, 1000 + b, "FLOW_MARK", testing::EncodeMsg(testing::FlowMark(3)));
    }
    if (damaged) out << "\xED\xA1\xDA\x01 cut";
}

TEST(LogSource, MaxPublishesEveryEventToAConsumerThatAnswersAndNothingElse) {
    Scratch dir("log_max");
    const std::string url = UdpmUrl(7738);
    WriteLog(dir.Path("run.lcmlog"), false);
    launch::ChildProcess rec = StartCsvRecord(dir, url);
    ASSERT_TRUE(WaitForStatus(url, rec));
    launch::ChildProcess source(
        {Bin("gyrocal-log-source"), dir.Path("run.lcmlog"), "--max", "--lcm-url", url},
        dir.Path("source.err"), dir.Path("source.err"));
    EXPECT_EQ(WaitExit(source, 30s).code, 0) << Slurp(dir.Path("source.err"));
    EXPECT_EQ(WaitExit(rec, 30s).code, 0);
    const std::string err = Slurp(dir.Path("source.err"));
    EXPECT_THAT(err, HasSubstr("published 50 of 51 events"));
    EXPECT_THAT(err, HasSubstr("(1 not on --channels or flow control)"));
    // THEN every sample of every batch was written, in order (one CSV line each after the header)
    const csv::CsvFile got = ReadCsvFile(dir.Path("out.csv"));
    ASSERT_EQ(got.rows.size(), 800u);
    for (size_t i = 1; i < got.rows.size(); ++i)
        ASSERT_GT(got.rows[i].time_s, got.rows[i - 1].time_s) << "row " << i;
}

TEST(LogSource, ADamagedLogPublishesNothingAndNamesTheByte) {
    Scratch dir("log_damaged");
    WriteLog(dir.Path("bad.lcmlog"), true);
    launch::ChildProcess source(
        {Bin("gyrocal-log-source"), dir.Path("bad.lcmlog"), "--max", "--lcm-url", UdpmUrl(7738)},
        dir.Path("source.err"), dir.Path("source.err"));
    const launch::ExitStatus s = WaitExit(source, 30s);
    EXPECT_TRUE(s.exited && s.code == 1) << s.Describe();
    const std::string err = Slurp(dir.Path("source.err"));
    EXPECT_THAT(err, HasSubstr("bad.lcmlog: byte "));
    EXPECT_THAT(err, HasSubstr("the file ends inside an event header"));
    EXPECT_THAT(err, HasSubstr("nothing published"));
    launch::ChildProcess bad_option(
        {Bin("gyrocal-log-source"), dir.Path("bad.lcmlog"), "--channels", "(("},
        dir.Path("opt.err"), dir.Path("opt.err"));
    EXPECT_EQ(WaitExit(bad_option, 10s).code, 2);
    EXPECT_THAT(Slurp(dir.Path("opt.err")), HasSubstr("--channels '((' is not a valid regular"));
}

}  // namespace
}  // namespace gyrocal::test
