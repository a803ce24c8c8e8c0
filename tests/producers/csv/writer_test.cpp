// CSV writing: exact microsecond time, shortest round-trip values, empty unknowns, the value
// in force at a time, and a write -> parse round trip in process.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>

#include "producers/csv/csv_file.hpp"
#include "producers/csv/csv_writer.hpp"
#include "producers/csv/fields.hpp"

namespace gyrocal::csv {
namespace {
constexpr int64_t kOrigin = 1'000'000'000'000'000;

TEST(CsvWriter, TimeIsExactToTheMicrosecond) {
    EXPECT_EQ(FormatTimeS(0), "0.000000");
    EXPECT_EQ(FormatTimeS(1), "0.000001");
    EXPECT_EQ(FormatTimeS(-1), "-0.000001");
    EXPECT_EQ(FormatTimeS(-1'000'001), "-1.000001");
    EXPECT_EQ(FormatTimeS(1'234'567'890'123), "1234567.890123");
    EXPECT_EQ(FormatTimeS(std::numeric_limits<int64_t>::min()), "-9223372036854.775808");
}

TEST(CsvWriter, ValuesReadBackToTheSameDouble) {
    // Property: for random doubles over many magnitudes, the printed text parses to the same bits.
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> mant(-10.0, 10.0);
    std::uniform_int_distribution<int> exp10(-12, 6);
    for (int i = 0; i < 20000; ++i) {
        const double v = mant(rng) * std::pow(10.0, exp10(rng));
        const Number n = ParseNumber(FormatValue(v));
        ASSERT_EQ(n.status, NumberStatus::kOk);
        ASSERT_EQ(n.value, v) << FormatValue(v);
    }
    EXPECT_EQ(FormatValue(2.5), "2.5");
    EXPECT_EQ(FormatValue(std::nan("")), "");
    EXPECT_EQ(FormatValue(INFINITY), "");
}

TEST(CsvWriter, LatestAtGivesTheReadingInForce) {
    LatestAt l;
    EXPECT_FALSE(l.At(100));
    l.Add(100, 1.0);
    l.Add(300, 3.0);
    l.Add(200, 2.0);  // late arrival from another channel
    EXPECT_FALSE(l.At(99));
    EXPECT_EQ(l.At(100), 1.0);
    EXPECT_EQ(l.At(250), 2.0);
    EXPECT_EQ(l.At(1000), 3.0);
}

TEST(CsvWriter, RowsParseBackThroughTheReader) {
    // GIVEN samples with noise, one without supply, with and without encoder/chamber readings
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 1e-3);
    std::ostringstream text;
    text << kRecordHeader << "\n";
    std::vector<gyro_sample_t> sent;
    for (int i = 0; i < 200; ++i) {
        gyro_sample_t s{};
        s.utime = kOrigin + i * 10'001;
        s.sensor_id = i % 2 ? "S02" : "S01";
        s.gyro_v = 2.5 + noise(rng);
        s.temp_v = 2.5 + 0.009 * (i * 0.01) + noise(rng);
        s.temp_c = 25.0 + (s.temp_v - 2.5) / 0.009;
        s.supply_v = i % 2 ? std::nan("") : 5.0 + noise(rng);
        sent.push_back(s);
        const std::optional<double> enc = i < 50 ? std::nullopt : std::optional(i * 0.45);
        const std::optional<double> air = i < 100 ? std::nullopt : std::optional(40.0 + noise(rng));
        text << FormatRecordRow(s, kOrigin, enc, air) << "\n";
    }
    std::istringstream in(text.str());
    const CsvFile f = ReadCsv(in, "rec.csv", sensor::TempTransfer{}, OnError::kStop);
    // THEN every value reads back bit-identical, unknown values read back as absent
    ASSERT_EQ(f.rows.size(), sent.size());
    for (size_t i = 0; i < sent.size(); ++i) {
        const CsvRow& r = f.rows[i];
        EXPECT_EQ(TimeUs(r.time_s), static_cast<long long>(i * 10'001));
        EXPECT_EQ(r.sensor_id, sent[i].sensor_id);
        EXPECT_EQ(r.gyro_v, sent[i].gyro_v);
        EXPECT_EQ(r.temp_v, sent[i].temp_v);
        EXPECT_EQ(r.temp_c, sent[i].temp_c);
        EXPECT_EQ(r.supply_v.has_value(), !std::isnan(sent[i].supply_v));
        if (r.supply_v) {
            EXPECT_EQ(*r.supply_v, sent[i].supply_v);
        }
        EXPECT_EQ(r.encoder_deg.has_value(), i >= 50);
        if (r.encoder_deg) {
            EXPECT_EQ(*r.encoder_deg, i * 0.45);
        }
        EXPECT_EQ(r.chamber_c.has_value(), i >= 100);
    }
}

}  // namespace
}  // namespace gyrocal::csv
