// The CSV parser: header in any order, every malformed case with its exact message
// (file, line, column, what is wrong, what is valid), stop vs skip policies.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "producers/csv/conversion_options.hpp"
#include "producers/csv/csv_file.hpp"
#include "producers/csv/fields.hpp"

namespace gyrocal::csv {
namespace {

using ::testing::HasSubstr;

const sensor::TempTransfer kDefault{2.5, 0.009};

CsvFile Read(const std::string& text, OnError policy = OnError::kStop,
             sensor::TempTransfer t = kDefault) {
    std::istringstream in(text);
    return ReadCsv(in, "f.csv", t, policy);
}

// The message of the CsvError that reading `text` under the stop policy throws ("" if none).
std::string ErrorOf(const std::string& text) {
    try {
        Read(text);
    } catch (const CsvError& e) {
        return e.what();
    }
    return "";
}

const std::string kHeader = "time_s,sensor_id,gyro_v,temp_v\n";

TEST(CsvHeader, ColumnsInAnyOrderAndUnknownColumnsNamed) {
    // GIVEN a header with columns shuffled and two unknown columns
    const CsvFile f = Read(
        "note,temp_v,chamber_c,sensor_id,gyro_v,supply_v,time_s,encoder_deg,operator\n"
        "a,2.5,24.5,S01,2.51,5.02,0.25,90.5,bob\n");
    // THEN every value lands in its field and the unknown names are listed once, in order
    ASSERT_EQ(f.rows.size(), 1u);
    const CsvRow& r = f.rows[0];
    EXPECT_EQ(r.line, 2);
    EXPECT_EQ(r.time_s, 0.25);
    EXPECT_EQ(r.sensor_id, "S01");
    EXPECT_EQ(r.gyro_v, 2.51);
    EXPECT_EQ(r.temp_v, 2.5);
    EXPECT_EQ(r.supply_v, 5.02);
    EXPECT_EQ(r.encoder_deg, 90.5);
    EXPECT_EQ(r.chamber_c, 24.5);
    EXPECT_THAT(f.unknown, ::testing::ElementsAre("note", "operator"));
}

TEST(CsvHeader, EachMissingRequiredColumnIsNamed) {
    const std::vector<std::string> required = {"time_s", "sensor_id", "gyro_v", "temp_v"};
    for (const std::string& missing : required) {
        std::string header;
        for (const std::string& c : required) {
            if (c != missing) header += (header.empty() ? "" : ",") + c;
        }
        EXPECT_EQ(ErrorOf(header + ",supply_v\n"),
                  "f.csv:1: column " + missing +
                      ": missing from the header; required columns are time_s, sensor_id, "
                      "gyro_v, temp_v (optional: temp_c, supply_v, encoder_deg, chamber_c, "
                      "time_since_power_s)");
    }
}

TEST(CsvHeader, DuplicateAndEmptyNamesAndEmptyFile) {
    EXPECT_EQ(ErrorOf("# comment first\ntime_s,sensor_id,gyro_v,temp_v,gyro_v\n"),
              "f.csv:2: column gyro_v: appears twice in the header; each column may appear once");
    EXPECT_EQ(ErrorOf("time_s,,sensor_id,gyro_v,temp_v\n"),
              "f.csv:1: column #2: empty column name in the header; every header field needs a "
              "name");
    EXPECT_THAT(ErrorOf(""), HasSubstr("f.csv:1: column time_s: no header row: the file is empty"));
}

TEST(CsvRows, NonNumericValueNamesLineAndColumn) {
    EXPECT_EQ(ErrorOf(kHeader + "0,S01,2.5,2.5\n0.01,S01,2.5x,2.5\n"),
              "f.csv:3: column gyro_v: '2.5x' is not a number; expected a finite decimal number");
    EXPECT_EQ(ErrorOf(kHeader + "zero,S01,2.5,2.5\n"),
              "f.csv:2: column time_s: 'zero' is not a number; expected a finite decimal number");
    EXPECT_EQ(ErrorOf("time_s,sensor_id,gyro_v,temp_v,supply_v\n0,S01,2.5,2.5,five\n"),
              "f.csv:2: column supply_v: 'five' is not a number; expected a finite decimal "
              "number");
}

TEST(CsvRows, NanAndInfAreRefusedInEveryNumericColumn) {
    for (const std::string bad : {"nan", "NaN", "inf", "-inf", "Infinity"}) {
        EXPECT_EQ(ErrorOf(kHeader + "0,S01,2.5," + bad + "\n"),
                  "f.csv:2: column temp_v: '" + bad +
                      "' is not finite; expected a finite "
                      "decimal number")
            << bad;
    }
    EXPECT_EQ(ErrorOf("time_s,sensor_id,gyro_v,temp_v,encoder_deg\n0,S01,2.5,2.5,nan\n"),
              "f.csv:2: column encoder_deg: 'nan' is not finite; expected a finite decimal "
              "number");
}

TEST(CsvRows, EmptyRequiredFieldIsRefusedEmptyOptionalMeansNotMeasured) {
    EXPECT_EQ(ErrorOf(kHeader + "0,S01,,2.5\n"),
              "f.csv:2: column gyro_v: empty; this column is required: a finite decimal number");
    const CsvFile f =
        Read("time_s,sensor_id,gyro_v,temp_v,supply_v,encoder_deg,chamber_c\n0,S01,2.5,2.5,,,\n");
    ASSERT_EQ(f.rows.size(), 1u);
    EXPECT_FALSE(f.rows[0].supply_v);
    EXPECT_FALSE(f.rows[0].encoder_deg);
    EXPECT_FALSE(f.rows[0].chamber_c);
}

TEST(CsvRows, TimeGoingBackwardsOrRepeatingPerSensor) {
    // Interleaved sensors each increasing: fine, although time goes back between sensors.
    EXPECT_EQ(ErrorOf(kHeader + "1.00,S01,2.5,2.5\n0.50,S02,2.5,2.5\n1.01,S01,2.5,2.5\n"), "");
    EXPECT_EQ(ErrorOf(kHeader + "1.00,S01,2.5,2.5\n0.50,S02,2.5,2.5\n0.99,S01,2.5,2.5\n"),
              "f.csv:4: column time_s: 0.99 is not after 1.00 of the previous S01 row "
              "(line 2); time_s must strictly increase per sensor (by at least 1 us)");
    EXPECT_THAT(ErrorOf(kHeader + "1.5,S01,2.5,2.5\n1.5,S01,2.5,2.5\n"),
                HasSubstr("f.csv:3: column time_s: 1.5 is not after 1.5 of the previous S01 row"));
    // Below the microsecond of utime two times are the same time.
    EXPECT_THAT(ErrorOf(kHeader + "1.0000001,S01,2.5,2.5\n1.0000002,S01,2.5,2.5\n"),
                HasSubstr("f.csv:3: column time_s:"));
    EXPECT_EQ(ErrorOf(kHeader + "1e10,S01,2.5,2.5\n"),
              "f.csv:2: column time_s: 1e10 is out of range; valid: -4e9 to 4e9 s");
    // Unix-epoch seconds are in range and keep the microsecond.
    const CsvFile epoch = Read(kHeader + "1795238709.529737,S01,2.5,2.5\n");
    EXPECT_EQ(TimeUs(epoch.rows.at(0).time_s), 1'795'238'709'529'737LL);
}

TEST(CsvRows, LineCutShortNamesTheFirstMissingColumn) {
    const std::string header = "time_s,sensor_id,gyro_v,temp_v,supply_v,chamber_c\n";
    EXPECT_EQ(ErrorOf(header + "0,S01,2.5,2.5,5.0,25\n0.01,S01,2.5\n"),
              "f.csv:3: column temp_v: missing: the line is cut short (3 of 6 fields); every line "
              "needs one field per header column");
    EXPECT_EQ(ErrorOf(header + "0,S01,2.5,2.5,5.0\n"),
              "f.csv:2: column chamber_c: missing: the line is cut short (5 of 6 fields); every "
              "line needs one field per header column");
    // A missing unknown column is still a short line.
    EXPECT_EQ(ErrorOf("time_s,sensor_id,gyro_v,temp_v,note\n0,S01,2.5,2.5\n"),
              "f.csv:2: column #5: missing: the line is cut short (4 of 5 fields); every line "
              "needs one field per header column");
    EXPECT_EQ(ErrorOf(kHeader + "0,S01,2.5,2.5,7\n"),
              "f.csv:2: column #5: line has 5 fields, the header has 4; every line needs exactly "
              "one field per header column");
}

TEST(CsvRows, InvalidSensorIds) {
    const std::vector<std::string> bad_ids = {"S 1", "S/1", "", "S01.", std::string(33, 'A')};
    for (const std::string& bad : bad_ids) {
        EXPECT_EQ(ErrorOf(kHeader + "0," + bad + ",2.5,2.5\n"),
                  "f.csv:2: column sensor_id: '" + bad +
                      "' is not a valid sensor id; use 1-32 letters, digits, '-' or '_'")
            << bad;
    }
    EXPECT_EQ(ErrorOf(kHeader + "0,unit-7_b,2.5,2.5\n0," + std::string(32, 'Z') + ",2.5,2.5\n"),
              "");
}

TEST(CsvRows, TempCFromTheTransferFunctionUnlessGiven) {
    // GIVEN a non-default transfer (1.8 V at 25 degC, 12 mV/K) and temperatures with known truth
    const sensor::TempTransfer t{1.8, 0.012};
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> temp(-40.0, 85.0);
    std::ostringstream text;
    text.precision(17);
    text << "time_s,sensor_id,gyro_v,temp_v\n";
    std::vector<double> truth_c;
    for (int i = 0; i < 50; ++i) {
        truth_c.push_back(temp(rng));
        text << i << ",S01,2.5," << 1.8 + 0.012 * (truth_c.back() - 25.0) << "\n";
    }
    const CsvFile f = Read(text.str(), OnError::kStop, t);
    ASSERT_EQ(f.rows.size(), truth_c.size());
    // THEN temp_c is the truth. Tolerance: temp_v carries 17 digits (relative error ~1e-16 of
    // ~2 V) which the 1/0.012 K/V slope turns into ~2e-14 K; 1e-9 K leaves a wide margin while
    // any wrong offset or slope (mK at least) fails.
    for (size_t i = 0; i < truth_c.size(); ++i) EXPECT_NEAR(f.rows[i].temp_c, truth_c[i], 1e-9);

    // A temp_c column wins; an empty temp_c field falls back to the transfer function.
    const CsvFile g = Read(
        "time_s,sensor_id,gyro_v,temp_v,temp_c\n0,S01,2.5,2.5,31.25\n"
        "1,S01,2.5,2.59,\n");
    ASSERT_EQ(g.rows.size(), 2u);
    EXPECT_EQ(g.rows[0].temp_c, 31.25);
    EXPECT_NEAR(g.rows[1].temp_c, 35.0, 1e-9);
}

TEST(CsvRows, BlanksQuotesCommentsAndCrlf) {
    const CsvFile f = Read(
        "# exported by DAQ\r\ntime_s, sensor_id ,gyro_v,temp_v\r\n\r\n"
        " 0.5 ,\"S01\", +2.5e0 ,2.5\r\n   \n# end\n");
    ASSERT_EQ(f.rows.size(), 1u);
    EXPECT_EQ(f.rows[0].line, 4);
    EXPECT_EQ(f.rows[0].sensor_id, "S01");
    EXPECT_EQ(f.rows[0].time_s, 0.5);
    EXPECT_EQ(f.rows[0].gyro_v, 2.5);
}

TEST(CsvPolicy, SkipDropsWholeRowsCountsThemAndKeepsTimeStateClean) {
    // GIVEN three bad rows among good ones; the bad time 5.0 must not block the good 2.0 after it
    const CsvFile f = Read(kHeader +
                               "0,S01,2.5,2.5\n"
                               "1,S01,abc,2.5\n"
                               "5,S01,2.5\n"
                               "2,S01,2.5,2.5\n"
                               "1.5,S01,2.5,2.5\n"
                               "3,S01,2.5,2.5\n",
                           OnError::kSkip);
    EXPECT_EQ(f.skipped, 3);
    ASSERT_EQ(f.errors.size(), 3u);
    EXPECT_THAT(f.errors[0], HasSubstr("f.csv:3: column gyro_v:"));
    EXPECT_THAT(f.errors[1], HasSubstr("f.csv:4: column temp_v: missing: the line is cut short"));
    EXPECT_THAT(f.errors[2], HasSubstr("f.csv:6: column time_s: 1.5 is not after 2"));
    ASSERT_EQ(f.rows.size(), 3u);
    EXPECT_EQ(f.rows[0].time_s, 0.0);
    EXPECT_EQ(f.rows[1].time_s, 2.0);
    EXPECT_EQ(f.rows[2].time_s, 3.0);
}

TEST(CsvPolicy, StopThrowsTheFirstErrorOnly) {
    try {
        Read(kHeader + "0,S01,2.5,2.5\n1,S01,abc,2.5\n2,S01,2.5\n");
        FAIL() << "expected a CsvError";
    } catch (const CsvError& e) {
        EXPECT_EQ(e.line(), 3);
        EXPECT_EQ(e.column(), "gyro_v");
    }
}

TEST(CsvFile, HeadCheckReadsOnlyTheFirstRows) {
    // GIVEN a bad row after the first three
    const std::string text =
        kHeader + "0,S01,2.5,2.5\n1,S01,2.5,2.5\n2,S01,2.5,2.5\n3,S01,abc,2.5\n";
    std::istringstream head(text), whole(text);
    // WHEN only the head is read THEN the three rows are there and the bad one was never parsed
    const CsvFile f = ReadCsv(head, "f.csv", kDefault, OnError::kStop, 3);
    EXPECT_EQ(f.rows.size(), 3u);
    // AND reading the whole file finds it
    EXPECT_THROW(ReadCsv(whole, "f.csv", kDefault, OnError::kStop), CsvError);
    // AND a head of 0 rows checks the header alone
    std::istringstream bad_header("a,b\n");
    EXPECT_THROW(ReadCsv(bad_header, "f.csv", kDefault, OnError::kStop, 0), CsvError);
}

TEST(CsvConversionOptions, PresetsAndRangesNameTheOption) {
    EXPECT_TRUE(sensor::PresetTransfer("610"));
    EXPECT_TRUE(sensor::PresetTransfer("613"));
    EXPECT_FALSE(sensor::PresetTransfer("612"));
    ConversionOptions o = ConversionOptions::Defaults();
    EXPECT_EQ(o.Validate(), "");
    std::string err;
    const auto t = o.Transfer(&err);
    ASSERT_TRUE(t);
    EXPECT_EQ(t->v_at_25c, 2.5);
    EXPECT_EQ(t->v_per_c, 0.009);
    o.temp_v_per_c = 0.010;
    EXPECT_EQ(o.Transfer(&err)->v_per_c, 0.010);  // an explicit value wins over the preset

    ConversionOptions bad = ConversionOptions::Defaults();
    bad.preset = "999";
    EXPECT_EQ(bad.Validate(), "--preset '999' is unknown; valid: 610 or 613");
    bad = ConversionOptions::Defaults();
    bad.temp_v_per_c = 0.0;
    EXPECT_THAT(bad.Validate(), HasSubstr("--temp-v-per-c 0 is out of range; valid: > 0"));
    bad = ConversionOptions::Defaults();
    bad.encoder_counts_per_rev = 0;
    EXPECT_THAT(bad.Validate(), HasSubstr("--encoder-counts-per-rev 0 is out of range"));
    bad = ConversionOptions::Defaults();
    bad.start_utime = -5;
    EXPECT_THAT(bad.Validate(), HasSubstr("--start-utime -5 is out of range; valid: 0 to 4e18"));
}

TEST(CsvFields, NumbersAreWholeFields) {
    EXPECT_EQ(ParseNumber("1.5").status, NumberStatus::kOk);
    EXPECT_EQ(ParseNumber("-1e-3").value, -1e-3);
    EXPECT_EQ(ParseNumber("1.5 V").status, NumberStatus::kNotANumber);
    EXPECT_EQ(ParseNumber("+").status, NumberStatus::kNotANumber);
    EXPECT_EQ(ParseNumber("").status, NumberStatus::kEmpty);
    EXPECT_EQ(ParseNumber("1e999").status, NumberStatus::kNotANumber);
}

}  // namespace
}  // namespace gyrocal::csv
