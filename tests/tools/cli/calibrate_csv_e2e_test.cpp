// Measured data through the same pipeline: a simulated run is written to CSV by
// gyrocal-csv-record (as another lab would hand us a file), then `gyrocal calibrate --source csv`
// runs the same detectors, fitter, compensator and recorder on it with no sequencer. While it
// replays, a second gyrocal-csv-record writes what crossed the bus: the round trip
// simulate -> CSV -> replay -> CSV must give back the same samples, digit for digit. The rig's
// offset also follows its supply (an effect announced to no one), and `gyrocal analyze` on the
// CSV-sourced run must find it: the closed loop on data that came "from another lab".
// Ports 7783 (recording the rig) and 7784 (the replay), this file's own.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/tools/cli/e2e_support.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;

std::vector<std::string> Lines(const std::string& path) {
    std::ifstream f(path);
    std::vector<std::string> out;
    for (std::string l; std::getline(f, l);) out.push_back(l);
    return out;
}

// The first `n` comma-separated fields of a CSV line, as text.
std::string Fields(const std::string& line, int n) {
    size_t end = 0;
    for (int i = 0; i < n; ++i) {
        end = line.find(',', i == 0 ? 0 : end + 1);
        if (end == std::string::npos) return line;
    }
    return line.substr(0, end);
}

// A gyrocal-csv-record on `url` as its STATUS heartbeats show it: rows_written of each (-1
// before its first flush). Build it before the recorder starts.
struct CsvRecordWatch {
    bus::Bus bus;
    std::vector<double> rows;
    explicit CsvRecordWatch(const std::string& url) : bus(bus::BusOptions{url}) {
        bus.Subscribe<status_t>(std::string(channels::kStatus),
                                [this](const status_t& m, const std::string&) {
                                    if (m.process != "gyrocal-csv-record") return;
                                    double n = -1;
                                    for (int i = 0; i < m.num_extra; ++i)
                                        if (m.extra_names[i] == "rows_written")
                                            n = m.extra_values[i];
                                    rows.push_back(n);
                                });
    }
    // Its first heartbeat: it has subscribed.
    bool Listening() {
        return testing::HandleUntil(
            bus, [&] { return !rows.empty(); }, 20s);
    }
    // Two heartbeats in a row (a second apart) with the same rows, after whatever was queued:
    // the writer has ended and every row the recorder heard is written.
    bool Settled() {
        return testing::HandleUntil(
            bus,
            [&] {
                const size_t n = rows.size();
                return n >= 2 && rows[n - 1] > 0 && rows[n - 1] == rows[n - 2];
            },
            30s);
    }
};

TEST(CalibrateFromCsv, SimulatedRunExportedThenCalibratedAsMeasuredData) {
    const std::string dir = FreshDir("gyrocal_csv_e2e");
    const std::string url_a = UdpmUrl(7783);
    const std::string url_b = UdpmUrl(7784);
    const std::string csv_a = dir + "/lab.csv", csv_b = dir + "/replayed.csv";

    // GIVEN a simulated five-setpoint run (one unit, fast thermal constants, negligible sensor
    // lag, an undeclared supply effect) written to CSV
    CsvRecordWatch watch_a(url_a);
    launch::ChildProcess rec_a(
        {GYROCAL_BIN "/gyrocal-csv-record", "--out", csv_a, "--lcm-url", url_a}, dir + "/rec_a.log",
        dir + "/rec_a.log");
    // The recorder subscribes before the rig's first sample.
    ASSERT_TRUE(watch_a.Listening()) << launch::ReadLog(dir + "/rec_a.log");
    launch::ChildProcess rig({GYROCAL_BIN "/gyrocal-sim-rig",
                              "--mode",
                              "builtin",
                              "--units",
                              "1",
                              "--seed",
                              "3",
                              "--speed",
                              "60",
                              "--profile=-30,0,30,60,80",
                              "--dwell-s",
                              "500",
                              "--package-tau-s",
                              "40",
                              "--ramp-c-per-min",
                              "10",
                              "--sensor-tau-s",
                              "0.1",
                              "--effect",
                              "supply=0.05",
                              "--lcm-url",
                              url_a,
                              "--truth-out",
                              dir + "/truth.json"},
                             dir + "/rig.log", dir + "/rig.log");
    auto rig_end = rig.Wait(300s);
    ASSERT_TRUE(rig_end.has_value()) << launch::ReadLog(dir + "/rig.log");
    ASSERT_EQ(rig_end->code, 0) << launch::ReadLog(dir + "/rig.log");
    ASSERT_TRUE(watch_a.Settled()) << launch::ReadLog(dir + "/rec_a.log");
    rec_a.Stop();
    const auto rows_a = Lines(csv_a);
    ASSERT_GT(rows_a.size(), 100000u) << "the recording is too short";
    // No sample missing: consecutive rows are exactly one 100 Hz period apart.
    for (size_t i = 2; i < rows_a.size(); ++i) {
        const double dt = std::stod(rows_a[i]) - std::stod(rows_a[i - 1]);
        ASSERT_NEAR(dt, 0.01, 1e-7) << "gap before row " << i << ": " << rows_a[i];
    }

    // WHEN it is calibrated as measured data, with a second recorder listening to the replay
    CsvRecordWatch watch_b(url_b);
    launch::ChildProcess rec_b(
        {GYROCAL_BIN "/gyrocal-csv-record", "--out", csv_b, "--lcm-url", url_b}, dir + "/rec_b.log",
        dir + "/rec_b.log");
    ASSERT_TRUE(watch_b.Listening()) << launch::ReadLog(dir + "/rec_b.log");
    const std::string db = dir + "/lab.db", out = dir + "/calibrate.out";
    launch::ChildProcess cal(
        {GYROCAL_BIN "/gyrocal", "calibrate", "--source", "csv", "--input", csv_a, "--db", db,
         "--lcm-url", url_b, "--log-dir", dir + "/logs", "--quiet", "--source-arg=--max",
         "--source-arg=--max-rate-hz=10000", "--wall-timeout-s", "300"},
        out, out);
    auto cal_end = cal.Wait(330s);
    ASSERT_TRUE(cal_end.has_value()) << launch::ReadLog(out);
    EXPECT_EQ(cal_end->code, 0) << launch::ReadLog(out);
    rec_b.Stop();

    // THEN the run is recorded like any other: every row, its plateaus and rotations, a fit
    const int64_t rows = static_cast<int64_t>(rows_a.size()) - 1;
    EXPECT_EQ(
        Sql(db).Int(
            "SELECT count(*) FROM gyro_samples g JOIN runs r USING(run_id) WHERE r.outcome='stop'"),
        rows);
    EXPECT_EQ(Sql(db).Int("SELECT count(*) FROM plateaus"), 5);
    EXPECT_EQ(Sql(db).Int("SELECT count(*) FROM sensitivity_points WHERE accepted=1"), 2 * 5);
    EXPECT_GE(Sql(db).Int("SELECT count(*) FROM coeff_sets"), 1);
    EXPECT_NE(launch::ReadLog(out).find("stop: end of data"), std::string::npos)
        << launch::ReadLog(out);
    // ... and the replayed samples are the recorded ones: time, sensor, gyro_v, temp_v, temp_c,
    // supply_v, encoder_deg identical as text (chamber_c is re-published at most once a second
    // of data time, so its latest value may trail by up to a second and is not compared).
    const auto rows_b = Lines(csv_b);
    ASSERT_EQ(rows_b.size(), rows_a.size());
    for (size_t i = 0; i < rows_a.size(); ++i)
        ASSERT_EQ(Fields(rows_b[i], 7), Fields(rows_a[i], 7)) << "row " << i;

    // AND the analysis of the CSV-sourced run names the supply effect with the rig's coefficient
    // (4 reported standard errors + 5 % for the measured-supply regressor; derivation in
    // calibrate_closed_loop_e2e_test.cpp) and cuts the held-out error.
    sqlite3* h = nullptr;
    sqlite3_open_v2(db.c_str(), &h, SQLITE_OPEN_READONLY, nullptr);
    sqlite3_stmt* st = nullptr;
    sqlite3_prepare_v2(h, "SELECT run_id FROM runs WHERE outcome='stop'", -1, &st, nullptr);
    ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
    const std::string run = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
    sqlite3_finalize(st);
    // The run records which file it came from: the input's SHA-256 as sha256sum computes it.
    sqlite3_prepare_v2(h, "SELECT config_json FROM runs WHERE outcome='stop'", -1, &st, nullptr);
    ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
    const auto config =
        nlohmann::json::parse(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)));
    sqlite3_finalize(st);
    sqlite3_close(h);
    launch::ChildProcess sum({"sha256sum", csv_a}, dir + "/sha256.txt", dir + "/sha256.err");
    ASSERT_TRUE(sum.Wait(60s).has_value());
    EXPECT_EQ(config.value("input_sha256", ""), launch::ReadLog(dir + "/sha256.txt").substr(0, 64))
        << config.dump();
    launch::ChildProcess an({GYROCAL_BIN "/gyrocal", "analyze", run, "--db", db, "--json"},
                            dir + "/analysis.json", dir + "/analyze.err");
    auto an_end = an.Wait(120s);
    ASSERT_TRUE(an_end.has_value());
    ASSERT_EQ(an_end->code, 0) << launch::ReadLog(dir + "/analyze.err");
    const auto result = nlohmann::json::parse(launch::ReadLog(dir + "/analysis.json"));
    const auto& sensor = result.at("sensors").at(0);
    ASSERT_EQ(sensor.at("added").size(), 1u) << sensor.dump(2);
    EXPECT_EQ(sensor.at("added").at(0).at("effect"), "supply");
    EXPECT_NEAR(sensor.at("added").at(0).at("coefficient").get<double>(), 0.05,
                4.0 * sensor.at("added").at(0).at("stderr").get<double>() + 0.05 * 0.05);
    // Same fitter before and after (calibrate_closed_loop_e2e_test.cpp says why half).
    EXPECT_LT(sensor.at("error_after").at("rate_rms_dps").get<double>(),
              0.5 * sensor.at("error_before").at("rate_rms_dps").get<double>());
}

}  // namespace
}  // namespace gyrocal
