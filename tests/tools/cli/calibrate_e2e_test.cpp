// The whole process graph, end to end, as separate OS processes over UDP multicast (TTL 0, this
// file's own port 7781): `gyrocal calibrate` starts the simulated rig, plateau detector, rotation
// estimator, fitter, compensator, recorder and sequencer, runs the seed's 3-point procedure on two
// units, and the test checks the result against the rig's truth sidecar and the SQLite file.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "gyrocal/model_t.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "processors/model/model.hpp"
#include "producers/sim/noise.hpp"
#include "tests/support/wait/wait_until.hpp"
#include "tests/tools/cli/e2e_support.hpp"
#include "tests/tools/cli/stored_model.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

const std::string kUrl = UdpmUrl(7781);

double TruthAt(const json& curve, double die_c) {
    const auto c = curve.at("coeffs").get<std::vector<double>>();
    const double d = die_c - curve.at("t0_c").get<double>();
    return c.at(0) + c.at(1) * d + c.at(2) * d * d;
}

TEST(CalibrateEndToEnd, Seed3OnTwoSimulatedUnitsAcrossRealProcesses) {
    const std::string dir = FreshDir("gyrocal_e2e");
    const std::string db = dir + "/run.db", out = dir + "/calibrate.out";
    // Fast thermal constants keep the simulated run short (~25 simulated minutes); the speed
    // keeps every process far below the rate at which the loaded 2-core machine loses packets.
    launch::ChildProcess cal(Joined({{GYROCAL_CLI, "calibrate", "--profile", "seed3"},
                                     SimRunArgs("2", "7", "40", db, kUrl, dir + "/logs"),
                                     kFastThermalArgs,
                                     {"--wall-timeout-s", "400"}}),
                             out, out);
    auto ended = cal.Wait(std::chrono::seconds(420));
    ASSERT_TRUE(ended.has_value()) << "calibrate did not finish:\n" << launch::ReadLog(out);
    ASSERT_TRUE(ended->exited && ended->code == 0) << ended->Describe() << "\n"
                                                   << launch::ReadLog(out);
    const std::string printed = launch::ReadLog(out);
    EXPECT_NE(printed.find("stop: completed"), std::string::npos) << printed;
    EXPECT_NE(printed.find("fitted vs true"), std::string::npos) << printed;

    const json truth = json::parse(launch::ReadLog(dir + "/logs/truth.json"));
    const json& noise = truth.at("config").at("noise");
    Sql sql(db);
    const std::string run =
        sql.Rows("SELECT run_id FROM runs WHERE run_id <> '' ORDER BY started_utime DESC")
            .at(0)
            .at(0);
    EXPECT_EQ(sql.Rows("SELECT outcome FROM runs WHERE run_id='" + run + "'").at(0).at(0), "stop");

    // Every published message is in the database: the rig's last heartbeat counts everything it
    // published (itself included); gyro samples, encoder samples, chamber states, the units'
    // power-on records and the rig's own heartbeats are all it publishes. And no sample is missing
    // by sequence number.
    const int64_t rig_published = sql.Int(
        "SELECT published FROM status WHERE process='gyrocal-sim-rig' ORDER BY published DESC "
        "LIMIT 1");
    const int64_t stored = sql.Int("SELECT count(*) FROM gyro_samples") +
                           sql.Int("SELECT count(*) FROM encoder_samples") +
                           sql.Int("SELECT count(*) FROM chamber_states") +
                           sql.Int("SELECT count(*) FROM power_states") +
                           sql.Int("SELECT count(*) FROM status WHERE process='gyrocal-sim-rig'");
    EXPECT_EQ(stored, rig_published);
    for (const auto& r : sql.Rows("SELECT sensor_id, count(*), min(seq), max(seq) FROM "
                                  "gyro_samples GROUP BY sensor_id")) {
        EXPECT_EQ(std::stoll(r[1]), std::stoll(r[3]) - std::stoll(r[2]) + 1)
            << "seq gaps for " << r[0];
        EXPECT_EQ(std::stoll(r[2]), 0) << r[0];
    }
    EXPECT_EQ(
        sql.Int("SELECT coalesce(sum(seq_gaps + decode_errors + queue_drops), 0) FROM losses"), 0);

    for (const json& unit : truth.at("units")) {
        const std::string id = unit.at("sensor_id");
        SCOPED_TRACE(id);
        // Plateaus: one per setpoint; rotations: +90 and -90 at each, all accepted.
        const auto plateaus =
            sql.Rows("SELECT temp_mean_c, gyro_mean_v, gyro_sem_v FROM plateaus WHERE run_id='" +
                     run + "' AND sensor_id='" + id + "' ORDER BY utime");
        ASSERT_EQ(plateaus.size(), 3u);
        EXPECT_EQ(sql.Int("SELECT count(*) FROM sensitivity_points WHERE accepted=1 AND run_id='" +
                          run + "' AND sensor_id='" + id + "'"),
                  6);
        // The final coefficient set, linked to exactly those plateaus (provenance).
        const std::string row = NewestCoeffRow(sql, run, id);
        ASSERT_FALSE(row.empty());
        EXPECT_EQ(sql.Int("SELECT count(*) FROM v_coeff_provenance WHERE coeff_row_id=" + row +
                          " AND kind='plateau' AND item_found=1"),
                  3);
        const model::Model offset = StoredModel(sql, row, "offset");
        const model::Model sens = StoredModel(sql, row, "sensitivity");
        EXPECT_EQ(offset.method, "3point");
        EXPECT_EQ(offset.term_names, (std::vector<std::string>{"1", "dT", "dT^2"}));
        model::Evaluator off_eval(offset), sens_eval(sens);

        // Offset at each plateau temperature vs the truth at the die temperature the sensor
        // reported (reading = die + its offset). Three points fix a quadratic, so agreement at
        // the three plateau temperatures is agreement of the coefficients. Tolerance, derived:
        //  - statistical: the plateau mean of a 60 s window is off the truth by the white noise
        //    averaged over it, N^2/tau, plus the SLOW noise's value then (bias instability's
        //    Gauss-Markov components and the rate random walk, as 60 s means about zero:
        //    sim::SlowNoiseBinVariance; the Allan deviation would understate it, as it measures
        //    differences, not the value), times the sensitivity; 4 sigma (two-sided 6e-5 per
        //    point);
        //  - systematic: at a plateau the sensor still lags the die by slope x sensor_tau, with
        //    slope <= the detector's 0.05 C/min, times the largest offset drift of the preset
        //    spread (1 mV/K).
        const double tau_s = 60.0;
        sim::NoiseConfig nc;
        nc.noise_density_dps_rthz = noise.at("noise_density_dps_rthz");
        nc.bias_instability_dps = noise.at("bias_instability_dps");
        nc.rate_random_walk_dps_rts = noise.at("rate_random_walk_dps_rts");
        const double run_s = 1e-6 * (sql.Int("SELECT max(utime) FROM gyro_samples") -
                                     sql.Int("SELECT min(utime) FROM gyro_samples"));
        const double sigma_rate_dps =
            std::sqrt(nc.noise_density_dps_rthz * nc.noise_density_dps_rthz / tau_s +
                      sim::SlowNoiseBinVariance(nc, tau_s, run_s));
        const double sensor_tau_s = truth.at("config").at("thermal").at("sensor_tau_s");
        const double systematic_v = 1.0e-3 * (0.05 / 60.0) * sensor_tau_s;
        const double sensor_offset_c = unit.at("temp_sensor_offset_c");
        for (const auto& p : plateaus) {
            const double temp_c = std::stod(p[0]);
            const double die_c = temp_c - sensor_offset_c;
            const double s_true = TruthAt(unit.at("sensitivity_v_per_dps"), die_c);
            const double tol_v = 4.0 * sigma_rate_dps * s_true + systematic_v;
            model::ModelInputs in;
            in.temp_c = temp_c;
            EXPECT_NEAR(off_eval.Value(in, model::RangePolicy::kClip),
                        TruthAt(unit.at("offset_v"), die_c), tol_v)
                << "offset at " << temp_c << " C";
            // Sensitivity: within 4 sigma of the fit's own uncertainty (phi' C phi) plus 0.1 %
            // for the encoder's quantization of a 90 deg move (1 count of 20000 per rev = 0.02 %).
            const model::Evaluation se = sens_eval.Evaluate(in, model::RangePolicy::kClip);
            EXPECT_NEAR(se.value, s_true, 4.0 * std::sqrt(se.variance) + 1e-3 * s_true)
                << "sensitivity at " << temp_c << " C";
        }
        // The still unit, compensated with the final set: the mean rate of every recorded still
        // sample in each plateau window is zero within the same budget, in deg/s.
        for (const auto& w : sql.Rows("SELECT start_utime, end_utime FROM plateaus WHERE run_id='" +
                                      run + "' AND sensor_id='" + id + "'")) {
            double sum_dps = 0;
            int count = 0;
            double temp_c = 0;
            for (const auto& g :
                 sql.Rows("SELECT gyro_v, temp_c FROM gyro_samples WHERE sensor_id='" + id +
                          "' AND utime BETWEEN " + w[0] + " AND " + w[1])) {
                model::ModelInputs in;
                in.temp_c = temp_c = std::stod(g[1]);
                sum_dps += (std::stod(g[0]) - off_eval.Value(in, model::RangePolicy::kClip)) /
                           sens_eval.Value(in, model::RangePolicy::kClip);
                ++count;
            }
            ASSERT_GT(count, 1000);
            EXPECT_NEAR(sum_dps / count, 0.0, 4.0 * sigma_rate_dps + systematic_v / 0.005)
                << "mean compensated rate at " << temp_c << " C";
        }
        // The live compensator published rates for this unit.
        EXPECT_GT(sql.Int("SELECT count(*) FROM rates WHERE sensor_id='" + id + "'"), 1000);
    }
}

bool AnyProcessMentions(const std::string& needle) {
    for (const auto& e : std::filesystem::directory_iterator("/proc")) {
        const std::string cmd = launch::ReadLog(e.path().string() + "/cmdline");
        if (cmd.find(needle) != std::string::npos &&
            e.path().filename() != std::to_string(getpid()))
            return true;
    }
    return false;
}

// Ctrl-C in the middle of a run: the run is recorded as aborted by the operator, calibrate exits
// 3, and no process of the graph is left behind.
TEST(CalibrateEndToEnd, InterruptAbortsTheRunCleanly) {
    const std::string dir = FreshDir("gyrocal_e2e_int");
    const std::string db = dir + "/run.db", out = dir + "/calibrate.out";
    const std::string url = UdpmUrl(7782);
    launch::ChildProcess cal({GYROCAL_CLI, "calibrate", "--sensors", "1", "--speed", "20", "--db",
                              db, "--lcm-url", url, "--log-dir", dir + "/logs", "--quiet"},
                             out, out);
    // Wait (bounded) until the run has started, as a person would before pressing Ctrl-C, and
    // is recording: samples of it are in the database.
    ASSERT_TRUE(testing::WaitUntil(
        [&] {
            return launch::ReadLog(dir + "/logs/gyrocal-sequencer.log").find("setpoint") !=
                   std::string::npos;
        },
        30s, 100ms))
        << launch::ReadLog(out);
    ASSERT_TRUE(testing::WaitUntil(
        [&] {
            try {
                return Sql(db).Int("SELECT count(*) FROM gyro_samples") > 0;
            } catch (const std::exception&) {
                return false;  // not created yet, or its schema not yet
            }
        },
        30s, 100ms))
        << launch::ReadLog(out);
    cal.Signal(SIGINT);
    auto ended = cal.Wait(60s);
    ASSERT_TRUE(ended.has_value()) << launch::ReadLog(out);
    EXPECT_TRUE(ended->exited);
    EXPECT_EQ(ended->code, 3) << launch::ReadLog(out);
    Sql sql(db);
    const auto run = sql.Rows("SELECT outcome, reason FROM runs WHERE run_id <> ''");
    ASSERT_EQ(run.size(), 1u);
    EXPECT_EQ(run[0][0], "abort");
    EXPECT_NE(run[0][1].find("operator"), std::string::npos) << run[0][1];
    EXPECT_FALSE(AnyProcessMentions("239.255.76.67:7782"))
        << "a process of the graph outlived calibrate";
}

}  // namespace
}  // namespace gyrocal
