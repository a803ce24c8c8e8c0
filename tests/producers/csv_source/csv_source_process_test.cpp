// gyrocal-csv-source with real processes, CSV -> gyrocal-csv-source -> udpm -> gyrocal-csv-record
// -> CSV: the same samples come back (counts equal, values identical at printed precision), at a
// chosen speed and at --max; --on-error skip drops and counts bad rows; --on-error stop publishes
// nothing.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/producers/producer_process_support.hpp"

namespace gyrocal::test {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

TEST(CsvRoundTrip, SpeedReplayGivesBackTheSameSamplesAndSensorFilterWorks) {
    // GIVEN 3 interleaved sensors, 3 s at 100 Hz, all optional columns, shuffled header
    Scratch dir("roundtrip_speed");
    const std::string url = UdpmUrl(7730);
    WriteSyntheticCsv(dir.Path("in.csv"), SyntheticSpec{});
    launch::ChildProcess all = StartCsvRecord(dir, url, "all.csv", "all.err");
    launch::ChildProcess some =
        StartCsvRecord(dir, url, "some.csv", "some.err", {"--sensors", "S01,S03"});
    ASSERT_TRUE(WaitForStatus(url, {&all, &some}));

    // WHEN replayed 10x faster than real time
    launch::ChildProcess source = StartCsvSource(dir, url, "in.csv", {"--speed", "10"});
    const launch::ExitStatus s = WaitExit(source, 20s);
    EXPECT_TRUE(s.exited && s.code == 0) << s.Describe() << Slurp(dir.Path("source.err"));
    EXPECT_EQ(WaitExit(all, 20s).code, 0);
    EXPECT_EQ(WaitExit(some, 20s).code, 0);

    // THEN the recorded files hold exactly the samples (the unknown column was warned about once)
    const std::string err = Slurp(dir.Path("source.err"));
    EXPECT_THAT(err, HasSubstr("ignoring unknown column(s) operator"));
    EXPECT_THAT(err, HasSubstr("published 900 of 900 rows"));
    const csv::CsvFile original = ReadCsvFile(dir.Path("in.csv"));
    ExpectSameSamples(original, ReadCsvFile(dir.Path("all.csv")));
    ExpectSameSamples(original, ReadCsvFile(dir.Path("some.csv")), {"S01", "S03"});
}

TEST(CsvRoundTrip, MaxSpeedLosesNothing) {
    // GIVEN 30000 rows (3 sensors, 100 s at 100 Hz); --max paces at the default 20000 msg/s (~1.5
    // s)
    Scratch dir("roundtrip_max");
    const std::string url = UdpmUrl(7731);
    WriteSyntheticCsv(dir.Path("in.csv"), SyntheticSpec{{"S01", "S02", "S03"}, 100.0, 100.0, 5});
    launch::ChildProcess rec = StartCsvRecord(dir, url);
    ASSERT_TRUE(WaitForStatus(url, rec));
    launch::ChildProcess source = StartCsvSource(dir, url, "in.csv", {"--max"});
    EXPECT_EQ(WaitExit(source, 30s).code, 0) << Slurp(dir.Path("source.err"));
    EXPECT_EQ(WaitExit(rec, 30s).code, 0);
    // THEN every sample arrived, unchanged
    ExpectSameSamples(ReadCsvFile(dir.Path("in.csv")), ReadCsvFile(dir.Path("out.csv")));
}

// good.csv, the synthetic run, and bad.csv, the same with three bad rows inserted; then a
// recorder listening on `url`.
launch::ChildProcess BadFileAndRecorder(const Scratch& dir, const std::string& url) {
    // The bad rows become lines 12, 24, 36.
    WriteGoodAndBad(dir, "bad.csv",
                    {{9, "op0,S01,0.095000,2.5,abc,5.0,0,25"},  // gyro_v not a number
                     {20, "op0,S02,0.2,2.5"},                   // cut short
                     {31, "op0,S03,0.000000,2.5,2.5,,0,25"}});  // S03 time goes back
    return StartCsvRecord(dir, url);
}

TEST(CsvRoundTrip, SkipPolicyDropsBadRowsWholeAndCountsThem) {
    Scratch dir("skip");
    const std::string url = UdpmUrl(7734);
    launch::ChildProcess rec = BadFileAndRecorder(dir, url);
    ASSERT_TRUE(WaitForStatus(url, rec));
    launch::ChildProcess source =
        StartCsvSource(dir, url, "bad.csv", {"--speed", "20", "--on-error", "skip"});
    EXPECT_EQ(WaitExit(source, 20s).code, 0);
    EXPECT_EQ(WaitExit(rec, 20s).code, 0);
    const std::string err = Slurp(dir.Path("source.err"));
    const std::string bad = dir.Path("bad.csv");
    EXPECT_THAT(err, HasSubstr("skipped: " + bad + ":12: column gyro_v: 'abc' is not a number"));
    EXPECT_THAT(err,
                HasSubstr("skipped: " + bad +
                          ":24: column gyro_v: missing: the line is cut short (4 of 8 fields)"));
    EXPECT_THAT(
        err,
        HasSubstr("skipped: " + bad +
                  ":36: column time_s: 0.000000 is not after 0.090000 of the previous S03 row"));
    EXPECT_THAT(err, HasSubstr("published 900 of 900 rows"));
    EXPECT_THAT(err, HasSubstr("skipped 3 bad rows"));
    // THEN exactly the good rows arrived
    ExpectSameSamples(ReadCsvFile(dir.Path("good.csv")), ReadCsvFile(dir.Path("out.csv")));
}

TEST(CsvRoundTrip, StopPolicyPublishesNothingFromABadFile) {
    Scratch dir("stop");
    const std::string url = UdpmUrl(7735);
    launch::ChildProcess rec = BadFileAndRecorder(dir, url);
    ASSERT_TRUE(WaitForStatus(url, rec));
    launch::ChildProcess source = StartCsvSource(dir, url, "bad.csv");
    const launch::ExitStatus s = WaitExit(source, 20s);
    EXPECT_TRUE(s.exited && s.code == 1) << s.Describe();
    EXPECT_EQ(WaitExit(rec, 20s).code, 0);
    EXPECT_THAT(Slurp(dir.Path("source.err")),
                HasSubstr("error: " + dir.Path("bad.csv") +
                          ":12: column gyro_v: 'abc' is not a number; expected a finite decimal "
                          "number\ngyrocal-csv-source: nothing published"));
    // THEN not one sample reached the recorder (not even the 10 good rows before the bad one)
    EXPECT_EQ(ReadCsvFile(dir.Path("out.csv")).rows.size(), 0u);
    EXPECT_THAT(Slurp(dir.Path("rec.err")), HasSubstr("wrote 0 rows"));
}

}  // namespace
}  // namespace gyrocal::test
