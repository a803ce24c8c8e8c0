// gyrocal-csv-source's node in one process over memq:// (LCM's in-process provider): a small
// measured-data file published on the node's own bus at a high --speed. Known truth: the values
// written in the file; every row is a sample at start + time_s with its values, numbered per
// sensor; the encoder once per time step; POWER_<id> from time_since_power_s. No sleep: Run()
// returns after the last row (--drain-s 0) and what it published last is handled after. The real
// process (round trips, --max, bad rows, exit codes): csv_source_process_test.cpp.
#include "producers/csv_source/csv_source_node.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/text/number.hpp"
#include "producers/csv/csv_file.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/producers/source_output.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;

TEST(CsvSourceNode, PublishesEveryRowWithItsValuesAtItsDataTime) {
    // GIVEN a file of two sensors, 10 rows each 10 ms apart, the table turning 2 deg per step,
    // each unit powered 100 s before the first row
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("gyrocal_csv_source_node_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    const std::string file = (dir / "in.csv").string();
    struct Row {
        int64_t us;
        std::string id;
        double gyro_v, temp_v;
    };
    std::vector<Row> rows;
    {
        std::ofstream out(file);
        out << "time_s,sensor_id,gyro_v,temp_v,temp_c,supply_v,encoder_deg,time_since_power_s\n";
        for (int i = 0; i < 10; ++i) {
            for (const char* id : {"S01", "S02"}) {
                const double gyro_v = 2.5 + 0.0007 * i + (id[2] == '2' ? 0.05 : 0.0);
                const double temp_v = 2.45 + 0.0003 * i;
                rows.push_back({i * 10'000, id, gyro_v, temp_v});
                // 17 significant digits: each value reads back exact.
                out << text::Sig(i * 0.01, 17) << ',' << id << ',' << text::Sig(gyro_v, 17) << ','
                    << text::Sig(temp_v, 17) << ",20,5," << 2 * i << ','
                    << text::Sig(100 + i * 0.01, 17) << '\n';
            }
        }
    }
    csv_source::CsvSourceOptions o = csv_source::CsvSourceOptions::Defaults();
    o.file = file;
    o.lcm_url = "memq://";
    o.speed = 1e6;  // 0.09 s of data in well under a millisecond
    o.drain_s = 0;
    ASSERT_EQ(o.Validate(), "");
    csv_source::CsvCheck check;
    {
        std::ifstream in(file);
        check.rows = static_cast<long>(
            csv::ReadCsv(in, file, sensor::TempTransfer{}, csv::OnError::kStop).rows.size());
    }
    ASSERT_EQ(check.rows, 20);
    csv_source::CsvSourceNode node(o, check);
    testing::SourceOutput out(node.bus());
    const auto& [gyro, encoder, chamber, power] = out;
    // WHEN the node publishes it
    EXPECT_EQ(node.Run(), 0);
    testing::DrainBus(node.bus());
    // THEN every row is a sample with its values, in file order, numbered per sensor
    testing::ExpectSamplesOfRows(gyro, rows, [&](const gyro_sample_t& g, size_t i) {
        EXPECT_EQ(g.temp_v, rows[i].temp_v);
        EXPECT_EQ(g.temp_c, 20.0);
        EXPECT_EQ(g.supply_v, 5.0);
    });
    // One encoder reading per time step, its angle the file's.
    ASSERT_EQ(encoder.size(), 10u);
    for (size_t i = 0; i < encoder.size(); ++i) {
        EXPECT_EQ(encoder[i].angle_deg, 2.0 * static_cast<double>(i));
        EXPECT_EQ(encoder[i].utime, csv::kDefaultStartUtime + static_cast<int64_t>(i) * 10'000);
    }
    // Each unit's power-on time, 100 s before the first row (within the rounding the format
    // allows a time_since_power_s, csv::kPowerOnToleranceUs).
    ASSERT_FALSE(power.empty());
    for (const power_state_t& p : power) {
        EXPECT_NEAR(static_cast<double>(p.power_on_utime),
                    static_cast<double>(csv::kDefaultStartUtime - 100'000'000),
                    static_cast<double>(csv::kPowerOnToleranceUs))
            << p.sensor_id;
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocal
