// Row -> messages: per-sensor seq, utime, NaN supply, encoder once per distinct time with
// counts from the angle, chamber state at most once per second of data time.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "producers/csv/row_messages.hpp"

namespace gyrocal::csv {
namespace {

CsvRow Row(double time_s, const std::string& id) {
    CsvRow r;
    r.time_s = time_s;
    r.sensor_id = id;
    r.gyro_v = 2.5 + time_s * 1e-3;
    r.temp_v = 2.6;
    r.temp_c = 36.1;
    return r;
}

TEST(CsvMessages, GyroSampleFieldsAndPerSensorSeq) {
    MessageBuilder b;
    std::vector<int64_t> seq_s01, seq_s02;
    for (int i = 0; i < 5; ++i) {
        for (const char* id : {"S01", "S02"}) {
            CsvRow r = Row(i * 0.01, id);
            if (std::string(id) == "S02") r.supply_v = 5.03;
            const RowMessages m = b.Build(r, StreamUtime(kDefaultStartUtime, r.time_s));
            (std::string(id) == "S01" ? seq_s01 : seq_s02).push_back(m.gyro.seq);
            EXPECT_EQ(m.gyro.sensor_id, id);
            EXPECT_EQ(m.gyro.gyro_v, r.gyro_v);
            EXPECT_EQ(m.gyro.temp_v, 2.6);
            EXPECT_EQ(m.gyro.temp_c, 36.1);
            EXPECT_FALSE(m.gyro.has_adc);
            EXPECT_EQ(m.gyro.gyro_counts, 0);
            EXPECT_EQ(m.gyro.supply_counts, -1);
            if (r.supply_v) {
                EXPECT_EQ(m.gyro.supply_v, 5.03);
            } else {
                EXPECT_TRUE(std::isnan(m.gyro.supply_v));
            }
            EXPECT_FALSE(m.encoder);
            EXPECT_FALSE(m.chamber);
        }
    }
    EXPECT_EQ(seq_s01, (std::vector<int64_t>{0, 1, 2, 3, 4}));
    EXPECT_EQ(seq_s02, (std::vector<int64_t>{0, 1, 2, 3, 4}));
}

TEST(CsvMessages, UtimeIsStartPlusMicroseconds) {
    EXPECT_EQ(StreamUtime(kDefaultStartUtime, 0.0), 1'000'000'000'000'000);
    EXPECT_EQ(StreamUtime(kDefaultStartUtime, 12.345678), 1'000'000'012'345'678);
    EXPECT_EQ(StreamUtime(kDefaultStartUtime, -0.000001), 999'999'999'999'999);
    // 1e9 s with a microsecond: exact, because it is rounded from a double that carries it.
    EXPECT_EQ(StreamUtime(2'000'000'000'000'000, 999999.000001), 2'000'999'999'000'001);
}

TEST(CsvMessages, EncoderOncePerDistinctTimeWithCountsFromTheAngle) {
    MessageBuilder b(20000);
    int published = 0;
    for (int i = 0; i < 4; ++i) {
        for (const char* id : {"S01", "S02", "S03"}) {
            CsvRow r = Row(i * 0.5, id);
            r.encoder_deg = 30.0 * i;
            const RowMessages m = b.Build(r, StreamUtime(kDefaultStartUtime, r.time_s));
            if (!m.encoder) continue;
            ++published;
            EXPECT_EQ(m.encoder->seq, i);
            EXPECT_EQ(m.encoder->utime, m.gyro.utime);
            EXPECT_EQ(m.encoder->angle_deg, 30.0 * i);
            EXPECT_EQ(m.encoder->counts, llround(30.0 * i * 20000 / 360.0));
            EXPECT_EQ(m.encoder->counts_per_rev, 20000);
            EXPECT_EQ(m.encoder->encoder_id, "TABLE");
        }
    }
    EXPECT_EQ(published, 4);  // 4 distinct times, 3 sensors each

    // Counts round to the nearest count, signed.
    MessageBuilder c(20000);
    CsvRow r = Row(0, "S01");
    r.encoder_deg = -90.0;
    EXPECT_EQ(c.Build(r, 1).encoder->counts, -5000);
    r = Row(1, "S01");
    r.encoder_deg = 90.0 + 0.4 * 360.0 / 20000;  // 0.4 count past 5000
    EXPECT_EQ(c.Build(r, 2).encoder->counts, 5000);
    r = Row(2, "S01");
    r.encoder_deg = 90.0 + 0.6 * 360.0 / 20000;
    EXPECT_EQ(c.Build(r, 3).encoder->counts, 5001);
}

TEST(CsvMessages, ChamberAtMostOncePerSecondOfDataTime) {
    // GIVEN chamber_c on every row at 100 Hz for 5.5 s
    MessageBuilder b;
    std::vector<double> times;
    std::vector<int64_t> seqs;
    for (int i = 0; i <= 550; ++i) {
        CsvRow r = Row(i / 100.0, "S01");
        r.chamber_c = 20.0 + i / 100.0;
        const RowMessages m = b.Build(r, StreamUtime(kDefaultStartUtime, r.time_s));
        if (!m.chamber) continue;
        times.push_back(r.time_s);
        seqs.push_back(m.chamber->seq);
        EXPECT_EQ(m.chamber->air_c, r.chamber_c);
        EXPECT_EQ(m.chamber->cmd_id, -1);
        EXPECT_TRUE(std::isnan(m.chamber->setpoint_c));
        EXPECT_FALSE(m.chamber->at_setpoint);
    }
    // THEN exactly one per whole second
    EXPECT_EQ(times, (std::vector<double>{0, 1, 2, 3, 4, 5}));
    EXPECT_EQ(seqs, (std::vector<int64_t>{0, 1, 2, 3, 4, 5}));

    // Irregular times: the next one is the first row at least 1 s after the last published.
    MessageBuilder c;
    std::vector<double> got;
    for (double t : {0.0, 0.7, 1.2, 1.9, 2.3, 2.31, 3.3}) {
        CsvRow r = Row(t, "S01");
        r.chamber_c = 25.0;
        if (c.Build(r, StreamUtime(kDefaultStartUtime, t)).chamber) got.push_back(t);
    }
    EXPECT_EQ(got, (std::vector<double>{0.0, 1.2, 2.3, 3.3}));
}

}  // namespace
}  // namespace gyrocal::csv
