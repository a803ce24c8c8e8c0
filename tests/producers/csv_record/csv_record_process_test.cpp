// gyrocal-csv-record with real processes: samples published directly on the bus, the ones that
// would not read back (not finite, time going back) refused and reported. The round trips through
// it are tests/producers/csv_source; a replayed LCM log, csv_record_lcm_log_process_test.cpp.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "gyrocal/gyro_sample_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "producers/csv/row_messages.hpp"
#include "tests/producers/producer_process_support.hpp"

namespace gyrocal::test {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

TEST(CsvRecord, RefusesSamplesThatWouldNotReadBack) {
    // GIVEN a recorder, and samples published directly: one with NaN gyro_v, one going back
    Scratch dir("record_guards");
    const std::string url = UdpmUrl(7737);
    launch::ChildProcess rec = StartCsvRecord(dir, url);
    ASSERT_TRUE(WaitForStatus(url, rec));
    {
        bus::Bus bus(bus::BusOptions{url});
        const int64_t t0 = csv::kDefaultStartUtime;
        const std::vector<std::pair<int64_t, double>> sent = {{t0, 2.5},
                                                              {t0 + 10'000, std::nan("")},
                                                              {t0 + 20'000, 2.6},
                                                              {t0 + 5'000, 2.7},
                                                              {t0 + 30'000, 2.8}};
        for (size_t i = 0; i < sent.size(); ++i) {
            gyro_sample_t s{};
            s.utime = sent[i].first;
            s.sensor_id = "S09";
            s.seq = static_cast<int64_t>(i);
            s.gyro_v = sent[i].second;
            s.temp_v = 2.5;
            s.temp_c = 25.0;
            s.supply_v = std::nan("");
            s.supply_counts = -1;
            bus.Publish(channels::Gyro("S09"), s);
        }
    }
    EXPECT_EQ(WaitExit(rec, 20s).code, 0);
    // THEN only the three good samples are written, and both refusals are reported
    const csv::CsvFile got = ReadCsvFile(dir.Path("out.csv"));
    ASSERT_EQ(got.rows.size(), 3u) << Slurp(dir.Path("rec.err"));
    EXPECT_EQ(got.rows[0].gyro_v, 2.5);
    EXPECT_EQ(got.rows[1].gyro_v, 2.6);
    EXPECT_EQ(got.rows[2].gyro_v, 2.8);
    EXPECT_EQ(csv::TimeUs(got.rows[2].time_s), 30'000);
    const std::string err = Slurp(dir.Path("rec.err"));
    EXPECT_THAT(err, HasSubstr("nonfinite_sample: GYRO_S09 seq 1: gyro_v or temp_v is not finite"));
    EXPECT_THAT(err, HasSubstr("out_of_order: GYRO_S09 seq 3: utime"));
}

}  // namespace
}  // namespace gyrocal::test
