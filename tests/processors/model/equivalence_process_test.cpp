// One model, one path, over real processes (port 7980, this file's own): one recorded run with an
// extended coefficient set holding each term kind (dT^3, dTdt(tau), dT*dTdt(tau), heating(w),
// supply, direction, warmup(tau), spline knots) gives the same rate for every sample
//   (1) live: gyrocal-compensator on the bus, its RATE_ messages as gyrocal-recorder stored them
//       (table rates),
//   (2) offline: `gyrocal compensate` on `gyrocal export --format samples` of the same run,
//   (3) firmware: the header `gyrocal export --format c-header` writes, compiled by the system C
//       compiler into firmware_program.c and fed the same CSV.
// The run is a synthetic CSV replayed by gyrocal-csv-source (temperature up, down and up again
// across the branch width, supply ripple, rotation both ways, power-on 12.5 s before the first
// sample in its time_since_power_s column), the set published on COEFFS_S01 before the source
// starts, so every sample is covered, warm-up included.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "processors/model/convert.hpp"
#include "tests/store/scratch_db.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
constexpr const char* kUrl = "udpm://239.255.76.67:7980?ttl=0&recv_buf_size=4194304";
constexpr const char* kRun = "equivalence-run";
constexpr int kSamples = 9000;  // 90 s at 100 Hz
constexpr double kPowerOnBeforeS = 12.5;

std::string Bin(const char* name) { return std::string(GYROCAL_BIN_DIR) + "/" + name; }

// The synthetic run: temperature 20 -> 32 -> 24 -> 30 degC (0.4, -0.32, 0.17 degC/s: dT/dt
// non-zero, the 1.5 degC branch crossed both ways), supply 5 V +- 50 mV, rotation +-30 deg/s.
std::string WriteCsv(const std::string& path) {
    std::ofstream f(path);
    f << "time_s,sensor_id,gyro_v,temp_v,temp_c,supply_v,time_since_power_s\n";
    char line[256];
    for (int i = 0; i < kSamples; ++i) {
        const double t = 0.01 * i;
        const double temp_c = t < 30   ? 20 + 0.4 * t
                              : t < 55 ? 32 - 0.32 * (t - 30)
                                       : 24 + (6.0 / 35.0) * (t - 55) + 0.02 * std::sin(3 * t);
        const double supply_v = 5.0 + 0.05 * std::sin(2 * M_PI * t / 40);
        const double rate_dps = 30 * std::sin(2 * M_PI * t / 7);
        const double gyro_v = 2.5 + 4e-4 * (temp_c - 25) + 0.005 * rate_dps +
                              3e-3 * std::exp(-(t + kPowerOnBeforeS) / 30);
        std::snprintf(line, sizeof line, "%.2f,S01,%.17g,%.17g,%.17g,%.17g,%.2f\n", t, gyro_v,
                      2.5 + 0.009 * (temp_c - 25), temp_c, supply_v, t + kPowerOnBeforeS);
        f << line;
    }
    return path;
}

// The inputs of sample i of WriteCsv's run by hand (gyrocal_model.h's definitions): dT/dt by the
// difference of exponential averages over tau = 20 s and 2 tau, the play operator of width
// 1.5 degC, time since a power-on kPowerOnBeforeS before the first sample.
struct HandInputs {
    double t_s, temp_c, rate_c_per_s, branch, supply_v, gyro_v, since_power_s;
};
HandInputs HandInputsAt(int i) {
    auto temp_at = [](double t) {
        return t < 30   ? 20 + 0.4 * t
               : t < 55 ? 32 - 0.32 * (t - 30)
                        : 24 + (6.0 / 35.0) * (t - 55) + 0.02 * std::sin(3 * t);
    };
    const double tau = 20.0, half = 0.75;
    double fast = temp_at(0), slow = fast, memory = fast;
    for (int k = 1; k <= i; ++k) {
        const double temp = temp_at(0.01 * k), dt = 0.01;
        fast += dt / (tau + dt) * (temp - fast);
        slow += dt / (2 * tau + dt) * (temp - slow);
        memory = std::min(std::max(memory, temp - half), temp + half);
    }
    HandInputs in;
    in.t_s = 0.01 * i;
    in.temp_c = temp_at(in.t_s);
    in.rate_c_per_s = (fast - slow) / tau;
    in.branch = (in.temp_c - memory) / half;
    in.supply_v = 5.0 + 0.05 * std::sin(2 * M_PI * in.t_s / 40);
    in.since_power_s = in.t_s + kPowerOnBeforeS;
    in.gyro_v = 2.5 + 4e-4 * (in.temp_c - 25) + 0.005 * 30 * std::sin(2 * M_PI * in.t_s / 7) +
                3e-3 * std::exp(-in.since_power_s / 30);
    return in;
}

// ExtendedSet's rate at those inputs, written out term by term.
double HandRate(const HandInputs& in) {
    const double dT = in.temp_c - 25;
    const double offset =
        2.5 + 4e-4 * dT + 3e-6 * dT * dT - 2e-8 * dT * dT * dT + 0.01 * in.rate_c_per_s +
        5e-4 * in.branch + 0.02 * (in.supply_v - model::kNominalSupplyV) +
        3e-3 * std::exp(-in.since_power_s / 30) + 4e-7 * std::pow(std::max(0.0, dT - 5.0), 3) -
        3e-7 * std::pow(std::max(0.0, -2.5 - dT), 3) - 2e-4 * dT * in.rate_c_per_s;
    const double direction = in.gyro_v - offset > 0 ? 1.0 : -1.0;
    return (in.gyro_v - offset) / (0.005 + 1e-6 * dT + 2e-5 * direction);
}

model::Model Model(const char* quantity, std::vector<std::string> terms, std::vector<double> c) {
    model::Model m;
    m.quantity = quantity;
    m.term_names = terms;
    m.coeffs = Eigen::Map<Eigen::VectorXd>(c.data(), static_cast<Eigen::Index>(c.size()));
    m.covariance = Eigen::MatrixXd::Identity(m.coeffs.size(), m.coeffs.size()) * 1e-14;
    m.t0_c = 25.0;
    m.temp_min_c = 10.0;
    m.temp_max_c = 40.0;
    m.n_points = 40;
    m.method = "analysis";
    return m;
}

// Each term kind at least once; one tracker configuration (dT/dt tau 20 s, branch width 1.5 degC).
coeff_set_t ExtendedSet() {
    model::CoeffSet s;
    s.utime = s.coeff_set_id = 4242;
    s.sensor_id = "S01";
    s.run_id = kRun;
    s.source = "analysis:1";
    s.offset = Model(model::kOffsetQuantity,
                     {"1", "dT", "dT^2", "dT^3", "dTdt(20)", "heating(1.5)", "supply", "warmup(30)",
                      "knot_above(5)", "knot_below(-2.5)", "dT*dTdt(20)"},
                     {2.5, 4e-4, 3e-6, -2e-8, 0.01, 5e-4, 0.02, 3e-3, 4e-7, -3e-7, -2e-4});
    s.sensitivity =
        Model(model::kSensitivityQuantity, {"1", "dT", "direction"}, {0.005, 1e-6, 2e-5});
    return model::ToMsg(s);
}

run_event_t RunEvent(const std::string& event) {
    run_event_t m{};
    m.utime = 1'000'000'000'000'000;
    m.run_id = kRun;
    m.event = event;
    m.setpoint_index = -1;
    m.setpoint_c = NAN;
    m.sensor_ids = {"S01"};
    m.num_sensors = 1;
    m.software_version = "test";
    m.config_json = "{}";
    return m;
}

struct Row {
    double rate_dps = NAN, angle_deg = NAN;
};

// time_s text (6 decimals, as the CSVs print it) -> rate and angle; the firmware's trailer line is
// skipped.
std::map<std::string, Row> ReadRates(const std::string& path, int rate_col, int angle_col) {
    std::map<std::string, Row> out;
    std::ifstream f(path);
    std::string line;
    std::getline(f, line);  // header
    while (std::getline(f, line)) {
        std::vector<std::string> fields;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');) fields.push_back(x);
        if (fields.size() <= static_cast<size_t>(std::max(rate_col, angle_col))) continue;
        if (fields[0] == "not_computable") continue;
        out[fields[0]] = {std::stod(fields[rate_col]), std::stod(fields[angle_col])};
    }
    return out;
}

std::string TimeText(int64_t utime) {
    char b[40];
    const int64_t us = utime - 1'000'000'000'000'000;
    std::snprintf(b, sizeof b, "%lld.%06lld", static_cast<long long>(us / 1'000'000),
                  static_cast<long long>(us % 1'000'000));
    return b;
}

std::map<std::string, Row> LiveRates(const std::string& db) {
    std::map<std::string, Row> out;
    sqlite3* h = nullptr;
    sqlite3_open_v2(db.c_str(), &h, SQLITE_OPEN_READONLY, nullptr);
    sqlite3_stmt* st = nullptr;
    sqlite3_prepare_v2(h,
                       "SELECT utime, rate_dps, angle_deg FROM rates WHERE sensor_id='S01' AND "
                       "run_id='equivalence-run' AND coeff_set_id=4242",
                       -1, &st, nullptr);
    while (st && sqlite3_step(st) == SQLITE_ROW)
        out[TimeText(sqlite3_column_int64(st, 0))] = {sqlite3_column_double(st, 1),
                                                      sqlite3_column_double(st, 2)};
    sqlite3_finalize(st);
    sqlite3_close(h);
    return out;
}

// Whether `sql` counts `want` within `timeout` (the recorder writes on its own schedule).
bool WaitForCount(const std::string& db, const std::string& sql, int64_t want,
                  std::chrono::seconds timeout) {
    return testing::WaitForCount(db, sql, want, timeout) == want;
}

int RunChild(const std::vector<std::string>& argv, const std::string& log) {
    launch::ChildProcess p(argv, log, log);
    const auto st = p.Wait(120s);
    return st ? st->code : -1;
}

struct Watcher {
    bus::Bus bus{bus::BusOptions{kUrl}};
    std::map<std::string, std::map<std::string, double>> extra;  // process -> counters
    Watcher() {
        bus.Subscribe<status_t>(std::string(channels::kStatus),
                                [this](const status_t& m, const std::string&) {
                                    for (size_t i = 0; i < m.extra_names.size(); ++i)
                                        extra[m.process][m.extra_names[i]] = m.extra_values[i];
                                    extra[m.process]["seen"] = 1;
                                });
    }
    double Get(const std::string& p, const std::string& k) {
        return extra.count(p) && extra[p].count(k) ? extra[p][k] : NAN;
    }
    template <class F>
    bool WaitFor(F&& cond, std::chrono::seconds timeout) {
        const auto end = std::chrono::steady_clock::now() + timeout;
        while (!cond()) {
            if (std::chrono::steady_clock::now() > end) return false;
            bus.Handle(50ms);
        }
        return true;
    }
};

TEST(ModelEquivalence, LiveOfflineAndFirmwareAgreeSampleForSample) {
    const std::string dir = ::testing::TempDir() + "gyrocal_equiv_" + std::to_string(getpid());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string db = dir + "/run.db", input = WriteCsv(dir + "/input.csv");

    // GIVEN the recorder and the live compensator listening, the run started and the extended
    // set applied before any sample
    Watcher w;
    launch::ChildProcess rec({Bin("gyrocal-recorder"), "--db", db, "--lcm-url", kUrl},
                             dir + "/rec.log", dir + "/rec.log");
    launch::ChildProcess comp({Bin("gyrocal-compensator"), "--lcm-url", kUrl}, dir + "/comp.log",
                              dir + "/comp.log");
    ASSERT_TRUE(w.WaitFor(
        [&] {
            return w.Get("gyrocal-recorder", "seen") == 1 &&
                   w.Get("gyrocal-compensator", "seen") == 1;
        },
        20s))
        << launch::ReadLog(dir + "/rec.log") << launch::ReadLog(dir + "/comp.log");
    w.bus.Publish(std::string(channels::kRunEvent), RunEvent("start"));
    ASSERT_TRUE(
        WaitForCount(db, "SELECT count(*) FROM runs WHERE run_id='equivalence-run'", 1, 20s));
    w.bus.Publish(channels::Coeffs("S01"), ExtendedSet());
    ASSERT_TRUE(
        w.WaitFor([&] { return w.Get("gyrocal-compensator", "coeff_sets_applied") == 1; }, 20s))
        << launch::ReadLog(dir + "/comp.log");
    ASSERT_TRUE(WaitForCount(db, "SELECT count(*) FROM coeff_sets", 1, 20s));

    // WHEN the CSV source replays the run
    ASSERT_EQ(RunChild({Bin("gyrocal-csv-source"), input, "--max", "--max-rate-hz", "4000",
                        "--lcm-url", kUrl},
                       dir + "/source.log"),
              0)
        << launch::ReadLog(dir + "/source.log");
    const std::string rates_sql = "SELECT count(*) FROM rates WHERE coeff_set_id=4242";
    ASSERT_TRUE(WaitForCount(db, rates_sql, kSamples, 60s))
        << testing::Count(db, rates_sql) << " rates stored of " << kSamples << "\n"
        << launch::ReadLog(dir + "/comp.log");
    ASSERT_TRUE(WaitForCount(db, "SELECT count(*) FROM gyro_samples", kSamples, 60s));
    w.bus.Publish(std::string(channels::kRunEvent), RunEvent("stop"));
    ASSERT_TRUE(WaitForCount(db,
                             "SELECT count(*) FROM runs WHERE run_id='equivalence-run' AND "
                             "stopped_utime IS NOT NULL",
                             1, 20s));
    // Every sample compensated live (none waiting for an input: warm-up had its power-on time).
    ASSERT_TRUE(
        w.WaitFor([&] { return w.Get("gyrocal-compensator", "compensated") == kSamples; }, 20s));
    EXPECT_EQ(w.Get("gyrocal-compensator", "uncompensated"), 0.0);
    EXPECT_EQ(w.Get("gyrocal-compensator", "power_on_assumed"), 0.0);
    EXPECT_EQ(comp.Stop().code, 0);
    EXPECT_EQ(rec.Stop().code, 0);

    // THEN the exported samples, compensated offline ...
    const std::string samples = dir + "/samples.csv", offline = dir + "/offline.csv";
    ASSERT_EQ(
        RunChild({GYROCAL_CLI, "export", kRun, "--db", db, "--format", "samples", "--out", samples},
                 dir + "/export.log"),
        0)
        << launch::ReadLog(dir + "/export.log");
    ASSERT_EQ(
        RunChild({GYROCAL_CLI, "compensate", samples, "--db", db, "--run", kRun, "--out", offline},
                 dir + "/compensate.log"),
        0)
        << launch::ReadLog(dir + "/compensate.log");
    EXPECT_EQ(launch::ReadLog(dir + "/compensate.log").find("not computable"), std::string::npos)
        << launch::ReadLog(dir + "/compensate.log");
    // ... and through the exported C header, compiled by the system C compiler
    const std::string header = dir + "/gyrocal_coeffs.h", program = dir + "/firmware";
    ASSERT_EQ(
        RunChild({GYROCAL_CLI, "export", kRun, "--db", db, "--format", "c-header", "--out", header},
                 dir + "/header.log"),
        0)
        << launch::ReadLog(dir + "/header.log");
    ASSERT_EQ(RunChild({GYROCAL_SYSTEM_CC, "-std=c99", "-O2", "-Wall", "-Werror", "-I", dir,
                        "-DGYROCAL_TEST_INIT=gyrocal_S01_init", GYROCAL_FIRMWARE_PROGRAM, "-o",
                        program, "-lm"},
                       dir + "/cc.log"),
              0)
        << launch::ReadLog(dir + "/cc.log");
    const std::string firmware = dir + "/firmware.csv";
    launch::ChildProcess fw({program, samples}, firmware, dir + "/firmware.err");
    const auto fw_end = fw.Wait(60s);
    ASSERT_TRUE(fw_end && fw_end->code == 0) << launch::ReadLog(dir + "/firmware.err");
    EXPECT_NE(launch::ReadLog(firmware).find("not_computable,0\n"), std::string::npos)
        << "the firmware left samples uncomputed";

    // Sample for sample, bit for bit: all three take the same doubles (the CSV prints the
    // shortest text that reads back to the same double, SQLite keeps 8-byte REALs, time and
    // power-on are whole microseconds) through the same C code (gyrocal_model.h, IEEE double,
    // no contraction into fused multiply-add: C99 mode, and the C++ build does not enable FMA),
    // with the same libm exp(). So the tolerance is zero.
    const auto live = LiveRates(db);
    const auto off = ReadRates(offline, 2, 3);
    const auto fwr = ReadRates(firmware, 1, 2);
    ASSERT_EQ(live.size(), static_cast<size_t>(kSamples));
    ASSERT_EQ(off.size(), static_cast<size_t>(kSamples));
    ASSERT_EQ(fwr.size(), static_cast<size_t>(kSamples));
    int differ = 0;
    for (const auto& [t, l] : live) {
        const auto o = off.find(t), f = fwr.find(t);
        ASSERT_NE(o, off.end()) << t;
        ASSERT_NE(f, fwr.end()) << t;
        ASSERT_TRUE(std::isfinite(l.rate_dps)) << t;
        const bool same = l.rate_dps == o->second.rate_dps && l.rate_dps == f->second.rate_dps &&
                          l.angle_deg == o->second.angle_deg && l.angle_deg == f->second.angle_deg;
        if (!same && differ++ < 5)
            ADD_FAILURE() << "t " << t << ": live " << l.rate_dps << " / " << l.angle_deg
                          << ", offline " << o->second.rate_dps << " / " << o->second.angle_deg
                          << ", firmware " << f->second.rate_dps << " / " << f->second.angle_deg;
    }
    EXPECT_EQ(differ, 0) << "samples whose rate or angle differ";
    // And the inputs are the run's: the first sample (t = 0, 20 degC, dT = -5, trackers just
    // started so dT/dt = branch = 0, supply at nominal) by hand. gyro_v was built with the linear
    // offset and the warm-up of a unit powered 12.5 s earlier, so gyro_v - offset_v leaves the
    // quadratic and cubic terms and the knot below -2.5 degC from t0 (dT = -5: 2.5^3):
    // -(3e-6 * 25 + 2e-8 * 125 - 3e-7 * 15.625) V, direction -1, sensitivity 0.005 - 5e-6 - 2e-5.
    // Had warm-up counted from the first sample (no power-on record), the offset would be 3 mV * (1
    // - exp(-12.5/30)) = 1 mV higher: 0.2 deg/s off. 1e-9 deg/s is rounding of the 2.5 V sums
    // (1e-15 V relative through 5 mV/(deg/s)) with a wide margin.
    const double expected = -(3e-6 * 25 + 2e-8 * 125 - 3e-7 * 15.625) / (0.005 - 5e-6 - 2e-5);
    EXPECT_NEAR(live.at("0.000000").rate_dps, expected, 1e-9);
    // At t = 58 s every input is in play: 3 s after the reversal at 55 s the temperature has
    // risen ~0.5 degC from its minimum, so the 1.5 degC branch is between its sides, dT/dt is
    // positive and still settling, the supply is off nominal and the warm-up has decayed to 1 %.
    // The inputs by hand from their documented definitions (an independent loop, not the model
    // library): the rate shares every sample's arithmetic with the trackers but not its order, so
    // it may differ in the last bits: 1e-9 deg/s is 1e-12 V through 5 mV/(deg/s), far above that
    // rounding and far below any input computed differently (a 0.01 s error in the power-on time
    // alone moves it by 5e-4 deg/s).
    const HandInputs in = HandInputsAt(5800);
    ASSERT_GT(in.branch, -1.0);
    ASSERT_LT(in.branch, 1.0);
    ASSERT_GT(in.rate_c_per_s, 0.0);
    EXPECT_NEAR(live.at("58.000000").rate_dps, HandRate(in), 1e-9);
    EXPECT_EQ(live.at("58.000000").rate_dps, off.at("58.000000").rate_dps);
    // At t = 28 s the temperature (31.2 degC, dT = 6.2) is 1.2 degC above the knot at 5: the
    // knot_above term (1.2^3) is in play, and so is the lag product dT x dT/dt (both nonzero).
    const HandInputs hot = HandInputsAt(2800);
    ASSERT_GT(hot.temp_c - 25.0, 5.0);
    ASSERT_NE(hot.rate_c_per_s, 0.0);
    EXPECT_NEAR(live.at("28.000000").rate_dps, HandRate(hot), 1e-9);
}

}  // namespace
}  // namespace gyrocal
