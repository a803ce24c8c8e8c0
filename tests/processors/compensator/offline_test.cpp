// Offline compensation of CSV rows (compensator/offline.hpp): the rates are the live library's on
// the same samples, the truth the rows were made from comes back, and bad input is refused naming
// the line, sensor or JSON field.
#include "processors/compensator/offline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "processors/model/json.hpp"
#include "tests/processors/compensator/coeff_set_fixture.hpp"

namespace gyrocal::compensator {
namespace {

// Rows of S01 at 100 Hz from the fixture's known set: temperature from 20 to 30 degC, a rate
// switching between +50 and -20 deg/s every second.
std::vector<csv::CsvRow> KnownRows(int n, std::vector<double>* truth_dps) {
    std::vector<csv::CsvRow> rows;
    for (int i = 0; i < n; ++i) {
        const double temp_c = 20.0 + 10.0 * i / n, rate = (i / 100) % 2 ? -20.0 : 50.0;
        const gyro_sample_t s = testing::KnownSample(i, temp_c, rate);
        csv::CsvRow r;
        r.line = i + 2;
        r.time_s = 0.01 * i;
        r.sensor_id = "S01";
        r.gyro_v = s.gyro_v;
        r.temp_v = s.temp_v;
        r.temp_c = temp_c;
        rows.push_back(r);
        truth_dps->push_back(rate);
    }
    return rows;
}

TEST(Offline, RatesAreTheLiveLibrarysOnTheSameSamplesAndRecoverTheTruth) {
    // GIVEN 1000 rows made from the known set, and that set
    std::vector<double> truth;
    const std::vector<csv::CsvRow> rows = KnownRows(1000, &truth);
    const model::CoeffSet set = model::FromMsg(testing::KnownSet(7, "R1"));
    // WHEN they are compensated offline
    const OfflineResult r = CompensateRows(rows, {{"S01", set}}, "in.csv", "sets.json");
    ASSERT_EQ(r.rates.size(), rows.size());
    EXPECT_EQ(r.skipped, 0);
    // THEN each rate equals, to the bit, what the live compensator's library gives for the
    // message a CSV source publishes (utime on the microsecond grid from the start time)
    SensorCompensator live(OfflineOptions::Defaults().core);
    ASSERT_EQ(live.SetCoefficients(set).outcome, SetOutcome::kApplied);
    for (size_t i = 0; i < rows.size(); ++i) {
        const int64_t utime = csv::StreamUtime(csv::kDefaultStartUtime, rows[i].time_s);
        const ApplyResult a =
            live.Apply({utime, static_cast<int64_t>(i), rows[i].gyro_v, rows[i].temp_c, NAN});
        ASSERT_EQ(a.status, ApplyStatus::kOk);
        EXPECT_EQ(r.rates[i].rate_dps, a.out.rate_dps) << i;
        EXPECT_EQ(r.rates[i].angle_deg, a.out.angle_deg) << i;
        EXPECT_EQ(r.rates[i].line, rows[i].line);
        EXPECT_EQ(r.rates[i].coeff_set_id, 7);
        // and the rate the rows were made from, to the rounding of gyro_v (1e-15 V over
        // 6 mV/(deg/s): 1e-12 deg/s; 1e-9 leaves room for the quadratic's evaluation)
        EXPECT_NEAR(r.rates[i].rate_dps, truth[i], 1e-9) << i;
    }
}

TEST(Offline, TheRatesCsvReadsBackToTheSameDoubles) {
    std::vector<double> truth;
    const OfflineResult r =
        CompensateRows(KnownRows(3, &truth), {{"S01", model::FromMsg(testing::KnownSet(1, ""))}},
                       "in.csv", "sets.json");
    std::istringstream in(FormatRatesCsv(r.rates));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "time_s,sensor_id,rate_dps,angle_deg,temp_c,range_flag");
    for (const OfflineRate& rate : r.rates) {
        ASSERT_TRUE(std::getline(in, line));
        std::istringstream cells(line);
        std::string time, sensor, rate_text;
        std::getline(cells, time, ',');
        std::getline(cells, sensor, ',');
        std::getline(cells, rate_text, ',');
        EXPECT_EQ(sensor, "S01");
        EXPECT_EQ(std::stod(rate_text), rate.rate_dps);
    }
}

TEST(Offline, BadInputIsRefusedNamingLineSensorOrField) {
    std::vector<double> truth;
    std::vector<csv::CsvRow> rows = KnownRows(2, &truth);
    rows[1].sensor_id = "S02";
    const model::CoeffSet set = model::FromMsg(testing::KnownSet(1, ""));
    // A row of a sensor without a set: its line, its sensor and the sensors the sets cover.
    try {
        CompensateRows(rows, {{"S01", set}}, "in.csv", "sets.json");
        FAIL() << "no error";
    } catch (const OfflineError& e) {
        EXPECT_NE(std::string(e.what()).find("in.csv:3: sensor_id 'S02'"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("(sets for: S01)"), std::string::npos) << e.what();
    }
    // Malformed JSON, and two sets for one sensor.
    EXPECT_THROW(CoeffSetsFromJson("{", "sets.json"), OfflineError);
    const std::string one = model::ToJson(set).dump();
    try {
        CoeffSetsFromJson("{\"coeff_sets\": [" + one + "," + one + "]}", "sets.json");
        FAIL() << "no error";
    } catch (const OfflineError& e) {
        EXPECT_NE(std::string(e.what()).find("sets.json"), std::string::npos) << e.what();
    }
    // One set object alone is read as it was written.
    const auto sets = CoeffSetsFromJson(one, "one.json");
    ASSERT_EQ(sets.size(), 1u);
    EXPECT_EQ(sets.at("S01").offset.coeffs, set.offset.coeffs);
}

}  // namespace
}  // namespace gyrocal::compensator
