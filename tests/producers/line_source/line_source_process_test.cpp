// gyrocal-line-source with real processes: a file piped to stdin comes back the same through
// gyrocal-csv-record, bad lines are skipped and counted with their line numbers; a FIFO read
// with --time wall stamps samples with the wall clock at reception; a stream without a valid
// header fails.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <thread>

#include "producers/csv/csv_writer.hpp"
#include "tests/producers/producer_process_support.hpp"

namespace gyrocal::test {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

std::string ShellQuote(const std::string& s) { return "'" + s + "'"; }

TEST(LineSource, PipedStreamGivesBackTheSameSamplesAndSkipsBadLines) {
    // GIVEN the synthetic stream with two bad lines after the 30th and 60th data lines
    Scratch dir("line_pipe");
    const std::string url = UdpmUrl(7732);
    WriteGoodAndBad(dir, "stream.txt",
                    {{29, "op0,S01,0.105,2.5,nan,5,0,25"},  // line 32
                     {59, "garbage"}});                     // line 63
    launch::ChildProcess rec = StartCsvRecord(dir, url);
    ASSERT_TRUE(WaitForStatus(url, rec));
    // WHEN it is piped into the line source (stdin is a pipe, not a file)
    launch::ChildProcess src(
        {"/bin/sh", "-c",
         "cat " + ShellQuote(dir.Path("stream.txt")) + " | exec " +
             ShellQuote(Bin("gyrocal-line-source")) + " --lcm-url " + ShellQuote(url)},
        "", dir.Path("src.err"));
    const launch::ExitStatus s = WaitExit(src, 20s);
    EXPECT_TRUE(s.exited && s.code == 0) << s.Describe() << Slurp(dir.Path("src.err"));
    EXPECT_EQ(WaitExit(rec, 20s).code, 0);
    // THEN the good samples arrive unchanged; the first bad line is named (later ones may be
    // rate-limited within the same second) and both are counted
    const std::string err = Slurp(dir.Path("src.err"));
    EXPECT_THAT(err, HasSubstr("stdin:32: column gyro_v: 'nan' is not finite"));
    EXPECT_THAT(err, HasSubstr("published 900 rows from stdin; skipped 2 bad lines"));
    ExpectSameSamples(ReadCsvFile(dir.Path("good.csv")), ReadCsvFile(dir.Path("out.csv")));
}

TEST(LineSource, WallTimeFromAFifo) {
    Scratch dir("line_fifo");
    const std::string url = UdpmUrl(7733);
    const std::string fifo = dir.Path("daq.fifo");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    launch::ChildProcess rec =
        StartCsvRecord(dir, url, "out.csv", "rec.err", {"--time-origin-utime", "0"});
    ASSERT_TRUE(WaitForStatus(url, rec));
    launch::ChildProcess src(
        {Bin("gyrocal-line-source"), "--device", fifo, "--time", "wall", "--lcm-url", url}, "",
        dir.Path("src.err"));
    // The open for writing waits for the source to open the FIFO for reading.
    const int fd = open(fifo.c_str(), O_WRONLY);
    ASSERT_GE(fd, 0);
    auto wall_us = [] {
        return std::chrono::duration_cast<std::chrono::microseconds>(
                   std::chrono::system_clock::now().time_since_epoch())
            .count();
    };
    // WHEN a DAQ writes 20 lines, 20 ms apart (the header arrives in two pieces)
    const std::string header = "time_s,sensor_id,gyro_v,temp_v\n";
    ASSERT_EQ(write(fd, header.data(), 10), 10);
    std::this_thread::sleep_for(20ms);  // time itself: the second piece arrives later
    ASSERT_EQ(write(fd, header.data() + 10, header.size() - 10),
              static_cast<ssize_t>(header.size() - 10));
    std::vector<int64_t> sent_us;
    for (int i = 0; i < 20; ++i) {
        const std::string line =
            std::to_string(i * 0.02) + ",DAQ1," + std::to_string(2.5 + i * 1e-3) + ",2.5\n";
        sent_us.push_back(wall_us());
        ASSERT_EQ(write(fd, line.data(), line.size()), static_cast<ssize_t>(line.size()));
        std::this_thread::sleep_for(20ms);  // time itself: a DAQ's pace, stamped at reception
    }
    close(fd);
    EXPECT_EQ(WaitExit(src, 20s).code, 0) << Slurp(dir.Path("src.err"));
    EXPECT_EQ(WaitExit(rec, 20s).code, 0);
    // THEN each sample is stamped at reception: not before it was written, and within the
    // source's 50 ms input poll plus scheduling (a generous 500 ms) after
    const csv::CsvFile got = ReadCsvFile(dir.Path("out.csv"));
    ASSERT_EQ(got.rows.size(), 20u);
    for (size_t i = 0; i < got.rows.size(); ++i) {
        const int64_t utime = csv::TimeUs(got.rows[i].time_s);
        EXPECT_GE(utime, sent_us[i]);
        EXPECT_LT(utime, sent_us[i] + 500'000);
        EXPECT_NEAR(got.rows[i].gyro_v, 2.5 + i * 1e-3, 1e-6);  // std::to_string keeps 6 decimals
    }
}

TEST(SourcesBadInput, LineSourceWithoutAValidHeaderFails) {
    Scratch dir("no_header");
    WriteText(dir.Path("s.txt"), "0,S01,2.5,2.5\n");
    launch::ChildProcess p({"/bin/sh", "-c",
                            "exec '" + Bin("gyrocal-line-source") + "' --lcm-url memq:// < '" +
                                dir.Path("s.txt") + "'"},
                           "", dir.Path("err"));
    EXPECT_EQ(WaitExit(p, 10s).code, 1);
    EXPECT_THAT(Slurp(dir.Path("err")),
                HasSubstr("stdin:1: column time_s: missing from the header; required columns are"));
}

}  // namespace
}  // namespace gyrocal::test
