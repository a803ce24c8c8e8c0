// gyrocal-csv-record's node in one process over memq:// (LCM's in-process provider): GYRO_S01,
// ENCODER, CHAMBER_STATE and POWER_S01 published on the node's own bus, then the file read back
// with the CSV reader gyrocal-csv-source uses. Known truth: every value is the one published, the
// encoder and chamber values are those in force at each sample's time, and the samples that
// would not read back are refused and counted. Bounded waits on conditions, no sleep. The real
// process over UDP: csv_record_process_test.cpp.
#include "producers/csv_record/csv_record_node.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "producers/csv/csv_file.hpp"
#include "tests/lcmtypes/bus/wire.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;

constexpr int64_t kT0 = csv::kDefaultStartUtime;  // [us] written as time_s = 0

gyro_sample_t Sample(const std::string& id, int64_t seq, int64_t utime, double gyro_v) {
    gyro_sample_t s{};
    s.utime = utime;
    s.sensor_id = id;
    s.seq = seq;
    s.gyro_v = gyro_v;
    s.temp_v = 2.4 + 1e-3 * static_cast<double>(seq);
    s.temp_c = 25.0;
    s.supply_v = 5.0;
    s.supply_counts = -1;
    return s;
}

encoder_sample_t Encoder(int64_t utime, int64_t seq, double angle_deg) {
    encoder_sample_t e{};
    e.utime = utime;
    e.encoder_id = "TABLE";
    e.seq = seq;
    e.counts_per_rev = 3600;
    e.counts = std::llround(angle_deg * 10.0);
    e.angle_deg = angle_deg;
    return e;
}

TEST(CsvRecordNode, WritesEachSampleWithTheValuesInForceAndRefusesWhatWouldNotReadBack) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("gyrocal_csv_record_node_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    csv_record::CsvRecordOptions o = csv_record::CsvRecordOptions::Defaults();
    o.out = (dir / "out.csv").string();
    o.lcm_url = "memq://";
    o.sensors = {"S01"};
    ASSERT_EQ(o.Validate(), "");
    csv_record::CsvRecordNode node(o);
    bus::Bus& bus = node.bus();

    // GIVEN the unit powered 60 s before t0, the chamber at 25 degC, the table at 0 deg, turned
    // to 90 deg at t0 + 15 ms
    power_state_t p{};
    p.utime = kT0;
    p.sensor_id = "S01";
    p.power_on_utime = kT0 - 60'000'000;
    p.source = "test";
    bus.Publish(channels::Power("S01"), p);
    chamber_state_t c{};
    c.utime = kT0;
    c.cmd_id = -1;
    c.setpoint_c = 25.0;
    c.air_c = 25.0;
    bus.Publish(std::string(channels::kChamberState), c);
    bus.Publish(std::string(channels::kEncoder), Encoder(kT0, 0, 0.0));
    bus.Publish(std::string(channels::kEncoder), Encoder(kT0 + 15'000, 1, 90.0));
    // WHEN S01 sends four good samples 10 ms apart, one NaN, one going back in time, a
    // non-finite encoder angle; and S02 (not in --sensors) one sample
    bus.Publish(channels::Gyro("S01"), Sample("S01", 0, kT0, 2.500));
    bus.Publish(channels::Gyro("S01"), Sample("S01", 1, kT0 + 10'000, 2.501));
    bus.Publish(channels::Gyro("S01"), Sample("S01", 2, kT0 + 20'000, std::nan("")));
    bus.Publish(channels::Gyro("S01"), Sample("S01", 3, kT0 + 20'000, 2.502));
    bus.Publish(channels::Gyro("S01"), Sample("S01", 4, kT0 + 5'000, 2.7));
    bus.Publish(std::string(channels::kEncoder), Encoder(kT0 + 25'000, 2, std::nan("")));
    bus.Publish(channels::Gyro("S01"), Sample("S01", 5, kT0 + 30'000, 2.503));
    bus.Publish(channels::Gyro("S02"), Sample("S02", 0, kT0 + 30'000, 2.9));
    const testing::Wire wire = testing::ForNode(node);
    ASSERT_TRUE(
        wire.until([&] { return node.rows_written() == 4 && node.rejected() == 3; }, 10'000ms))
        << node.rows_written() << " rows, " << node.rejected() << " refused";
    ASSERT_EQ(node.Finish(), 0);

    // THEN the file holds the four good samples, each as published, with the encoder angle and
    // chamber air in force at its time (the NaN angle refused: 90 deg stays in force) and the
    // time since power-on from POWER_S01
    std::ifstream in(o.out);
    const csv::CsvFile got = csv::ReadCsv(in, o.out, sensor::TempTransfer{}, csv::OnError::kStop);
    ASSERT_EQ(got.rows.size(), 4u);
    const double gyro_v[] = {2.500, 2.501, 2.502, 2.503};
    const int64_t t_us[] = {0, 10'000, 20'000, 30'000};
    const int64_t seq[] = {0, 1, 3, 5};
    const double encoder_deg[] = {0.0, 0.0, 90.0, 90.0};
    for (size_t i = 0; i < 4; ++i) {
        SCOPED_TRACE(i);
        const csv::CsvRow& r = got.rows[i];
        EXPECT_EQ(r.sensor_id, "S01");
        EXPECT_EQ(csv::TimeUs(r.time_s), t_us[i]);
        // Written in the shortest form that reads back to the same double: exact.
        EXPECT_EQ(r.gyro_v, gyro_v[i]);
        EXPECT_EQ(r.temp_v, Sample("S01", seq[i], 0, 0.0).temp_v);
        EXPECT_EQ(r.supply_v, 5.0);
        EXPECT_EQ(r.encoder_deg, encoder_deg[i]);
        EXPECT_EQ(r.chamber_c, 25.0);
        ASSERT_TRUE(r.time_since_power_s.has_value());
        EXPECT_NEAR(*r.time_since_power_s, 60.0 + 1e-6 * static_cast<double>(t_us[i]), 1e-9);
    }
    std::filesystem::remove_all(dir);
}

TEST(CsvRecordNode, AnOutFileThatCannotBeCreatedIsAnOptionError) {
    csv_record::CsvRecordOptions o = csv_record::CsvRecordOptions::Defaults();
    o.out = "/nonexistent-dir/out.csv";
    o.lcm_url = "memq://";
    try {
        csv_record::CsvRecordNode node(o);
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "--out '/nonexistent-dir/out.csv' cannot be created");
    }
}

}  // namespace
}  // namespace gyrocal
