// Multi-process: the real gyrocal-sim-rig over UDP multicast on this test's own port (7720).
// GIVEN the rig running at 100x with fast thermal constants, WHEN the test sends a CHAMBER_CMD,
// a TURNTABLE_CMD +90 and an impossible CHAMBER_CMD, THEN GYRO_<id> samples arrive with
// contiguous seq, ENCODER ends the move at 90 deg within one count, CHAMBER_STATE echoes the
// accepted order with the air moving toward it, and the refusal shows as fault and in STATUS.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>

#include "gyrocal/chamber_cmd_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/status_t.hpp"
#include "gyrocal/turntable_cmd_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/flow/flow_acker.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/lcmtypes/message_builders.hpp"
#include "tests/producers/sim_rig/rig_orders.hpp"

namespace gyrocal {
namespace {

const std::string kUrl = "udpm://239.255.76.67:7720?ttl=0&recv_buf_size=4194304";

struct Seen {
    std::map<std::string, std::vector<gyro_sample_t>> gyro;
    std::vector<encoder_sample_t> encoder;
    std::vector<chamber_state_t> chamber;
    std::vector<status_t> status;
};

using testing::HandleUntil;

// Handles `bus` while `rig` runs (at most 30 s), then until the bus is quiet; the rig's exit
// status, none if it was still running.
std::optional<launch::ExitStatus> PumpUntilExit(bus::Bus& bus, launch::ChildProcess& rig) {
    std::optional<launch::ExitStatus> st;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!(st = rig.Poll()) && std::chrono::steady_clock::now() < end) {
        bus.Handle(std::chrono::milliseconds(20));
    }
    while (bus.Handle(std::chrono::milliseconds(100))) {
    }
    return st;
}

TEST(SimRigProcess, ObeysCommandsAndPublishesContiguousSamples) {
    const std::string dir = ::testing::TempDir();
    const std::string truth = dir + "/sim_rig_process_truth.json";
    std::remove(truth.c_str());
    bus::Bus bus(bus::BusOptions{kUrl});
    Seen seen;
    bus.Subscribe<gyro_sample_t>(
        channels::AllSensors(channels::kGyroPrefix),
        [&](const gyro_sample_t& m, const std::string&) { seen.gyro[m.sensor_id].push_back(m); });
    testing::CollectInto(bus, std::string(channels::kEncoder), seen.encoder);
    testing::CollectInto(bus, std::string(channels::kChamberState), seen.chamber);
    bus.Subscribe<status_t>(std::string(channels::kStatus),
                            [&](const status_t& m, const std::string&) {
                                if (m.process == "gyrocal-sim-rig") seen.status.push_back(m);
                            });

    launch::ChildProcess rig({GYROCAL_SIM_RIG_EXE, "--lcm-url", kUrl, "--speed", "50", "--units",
                              "2", "--seed", "11", "--ramp-c-per-min", "60", "--air-tau-s", "2",
                              "--package-tau-s", "10", "--sensor-tau-s", "2", "--truth-out", truth},
                             dir + "/sim_rig_process.out", dir + "/sim_rig_process.err");

    // GIVEN the rig is up (its first CHAMBER_STATE arrived)
    ASSERT_TRUE(HandleUntil(
        bus, [&] { return !seen.chamber.empty(); }, std::chrono::seconds(10)))
        << "no CHAMBER_STATE from gyrocal-sim-rig";
    EXPECT_EQ(seen.chamber.front().cmd_id, -1);

    // WHEN orders arrive
    bus.Publish(std::string(channels::kChamberCmd), testing::ImpossibleChamberOrder());
    ASSERT_TRUE(HandleUntil(
        bus, [&] { return !seen.chamber.back().fault.empty(); }, std::chrono::seconds(5)));
    chamber_cmd_t cmd{};
    cmd.cmd_id = 7;
    cmd.setpoint_c = 35.0;
    cmd.ramp_rate_c_per_min = 0.0;
    bus.Publish(std::string(channels::kChamberCmd), cmd);
    bus.Publish(std::string(channels::kTurntableCmd), testing::QuarterTurn());

    // THEN the chamber follows: cmd echoed, air within tolerance of 35 degC (10 K at 60 K/min)
    ASSERT_TRUE(HandleUntil(
        bus, [&] { return seen.chamber.back().cmd_id == 7 && seen.chamber.back().at_setpoint; },
        std::chrono::seconds(10)));
    EXPECT_TRUE(seen.chamber.back().fault.empty()) << "an accepted order clears the fault";
    EXPECT_DOUBLE_EQ(seen.chamber.back().setpoint_c, 35.0);
    // and the table has finished its move (30 deg/s default: 3.5 s sim) and rests
    ASSERT_TRUE(HandleUntil(
        bus,
        [&] {
            return seen.encoder.size() > 100 &&
                   std::abs(seen.encoder.back().angle_deg - 90.0) < 1.0 &&
                   seen.encoder.back().counts == seen.encoder[seen.encoder.size() - 50].counts;
        },
        std::chrono::seconds(10)));
    ASSERT_TRUE(HandleUntil(
        bus, [&] { return seen.status.size() >= 2; }, std::chrono::seconds(5)));
    const launch::ExitStatus st = rig.Stop();
    EXPECT_TRUE(st.exited && st.code == 0) << st.Describe();
    // Drain what was still queued.
    while (bus.Handle(std::chrono::milliseconds(50))) {
    }

    const encoder_sample_t& last = seen.encoder.back();
    const double count_deg = 360.0 / last.counts_per_rev;
    EXPECT_EQ(last.counts_per_rev, 10000);
    EXPECT_NEAR(last.angle_deg - seen.encoder.front().angle_deg, 90.0, count_deg + 1e-9);
    for (size_t i = 1; i < seen.encoder.size(); ++i) {
        ASSERT_EQ(seen.encoder[i].seq, seen.encoder[i - 1].seq + 1) << "encoder seq gap at " << i;
        ASSERT_GT(seen.encoder[i].utime, seen.encoder[i - 1].utime);
    }

    ASSERT_EQ(seen.gyro.size(), 2u);
    for (const auto& [id, samples] : seen.gyro) {
        ASSERT_GT(samples.size(), 500u) << id;
        for (size_t i = 1; i < samples.size(); ++i) {
            ASSERT_EQ(samples[i].seq, samples[i - 1].seq + 1) << id << " seq gap at " << i;
            ASSERT_EQ(samples[i].utime - samples[i - 1].utime, testing::kPeriodUs)
                << id << " 100 Hz sim time";
        }
        EXPECT_GE(samples.front().utime, testing::kT0Utime) << "sim clock";
        EXPECT_TRUE(samples.back().has_adc);
        // Die (tau 10 s) and sensor follow the air toward 35 degC from 25 degC; a unit's sensor
        // has its own offset (2 degC sigma), so compare the change, not the level.
        EXPECT_GT(samples.back().temp_c - samples.front().temp_c, 3.0) << id;
    }
    EXPECT_EQ(bus.counters().seq_gaps, 0);

    // STATUS counted the refusal
    EXPECT_GE(seen.status.back().rejected, 1);
    EXPECT_NE(seen.status.back().last_reject.find("setpoint"), std::string::npos);

    // Truth sidecar written, functions of die temperature, with the units
    std::ifstream f(truth);
    ASSERT_TRUE(f.good());
    const auto j = nlohmann::json::parse(f);
    EXPECT_EQ(j["truth_temperature"], "die_c");
    EXPECT_EQ(j["units"].size(), 2u);
    EXPECT_EQ(j["seed"], 11);
}

TEST(SimRigProcess, BuiltinProfileRunsWithoutASequencerAndExits) {
    // GIVEN the rig in builtin mode with a short two-setpoint profile (port 7722)
    const std::string url = "udpm://239.255.76.67:7722?ttl=0&recv_buf_size=4194304";
    const std::string dir = ::testing::TempDir();
    bus::Bus bus(bus::BusOptions{url});
    std::vector<encoder_sample_t> encoder;
    std::vector<chamber_state_t> chamber;
    int64_t gyro = 0;
    testing::CollectInto(bus, std::string(channels::kEncoder), encoder);
    testing::CollectInto(bus, std::string(channels::kChamberState), chamber);
    bus.Subscribe<gyro_sample_t>(channels::AllSensors(channels::kGyroPrefix),
                                 [&](const gyro_sample_t&, const std::string&) { ++gyro; });
    const auto wall_start = std::chrono::steady_clock::now();
    launch::ChildProcess rig(
        {GYROCAL_SIM_RIG_EXE, "--lcm-url", url, "--mode", "builtin", "--profile", "20,30",
         "--dwell-s", "20", "--rest-s", "5", "--ramp-c-per-min", "60", "--air-tau-s", "2",
         "--speed", "100", "--units", "1"},
        dir + "/sim_rig_builtin.out", dir + "/sim_rig_builtin.err");
    // WHEN it runs (about 110 simulated s at 100x)
    const std::optional<launch::ExitStatus> st = PumpUntilExit(bus, rig);
    // THEN it finished by itself with exit 0, having visited both setpoints and rotated twice
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    ASSERT_TRUE(st.has_value()) << "builtin profile did not finish";
    // Paced: 100 simulated seconds per wall second, never faster.
    ASSERT_FALSE(chamber.empty());
    const double sim_s = (chamber.back().utime - chamber.front().utime) * 1e-6;
    EXPECT_GE(wall_s, sim_s / 100.0);
    EXPECT_TRUE(st->exited && st->code == 0) << st->Describe();
    ASSERT_FALSE(chamber.empty());
    EXPECT_EQ(chamber.back().cmd_id, 2);
    EXPECT_DOUBLE_EQ(chamber.back().setpoint_c, 30.0);
    int ups = 0;
    for (size_t i = 1; i < encoder.size(); ++i) {
        if (encoder[i - 1].angle_deg < 89.0 && encoder[i].angle_deg >= 89.0) ++ups;
    }
    EXPECT_EQ(ups, 2);
    EXPECT_GT(gyro, 5000);
    EXPECT_EQ(bus.counters().seq_gaps, 0);
}

// The same seed gives the same bytes through the real process too (builtin mode is driven by
// simulated time only, so wall-clock pacing cannot change it); another seed gives other bytes.
// The rig runs at the pace of this test process (--speed 0, the test acks its flow marks like
// every gyrocal process): at a fixed --speed 200 a loaded machine (CI's clone under a load of
// 15-30) delivered 1131746 of 1386154 bytes to the second run.
TEST(SimRigProcess, SameSeedSameSamplesAcrossRuns) {
    const std::string url = "udpm://239.255.76.67:7723?ttl=0&recv_buf_size=4194304";
    const std::string dir = ::testing::TempDir();
    auto run = [&](const std::string& seed) {
        bus::Bus bus(bus::BusOptions{url});
        flow::FlowAcker acker(bus, "sim_rig_process_test");
        std::string bytes;
        bus.Subscribe<gyro_sample_t>(channels::AllSensors(channels::kGyroPrefix),
                                     [&](const gyro_sample_t& m, const std::string&) {
                                         const auto buf = testing::EncodeMsg(m);
                                         bytes.append(buf.begin(), buf.end());
                                     });
        launch::ChildProcess rig(
            {GYROCAL_SIM_RIG_EXE, "--lcm-url", url, "--mode", "builtin", "--profile", "30",
             "--dwell-s", "5", "--rest-s", "2", "--ramp-c-per-min", "60", "--speed", "0", "--units",
             "2", "--seed", seed},
            dir + "/sim_rig_seed.out", dir + "/sim_rig_seed.err");
        const std::optional<launch::ExitStatus> st = PumpUntilExit(bus, rig);
        EXPECT_TRUE(st.has_value() && st->exited && st->code == 0);
        EXPECT_EQ(bus.counters().seq_gaps, 0) << "lost packets would make this comparison moot";
        return bytes;
    };
    const std::string a = run("5");
    const std::string b = run("5");
    const std::string c = run("6");
    ASSERT_GT(a.size(), 10000u);
    EXPECT_EQ(a.size(), b.size());
    EXPECT_TRUE(a == b) << "same seed, different samples";
    EXPECT_FALSE(a == c) << "different seeds, same samples";
}

TEST(SimRigProcess, BadOptionsExitTwo) {
    const std::string dir = ::testing::TempDir();
    // (--speed 0 is valid since flow control: no fixed speed, as fast as the consumers answer.)
    for (std::vector<std::string> args : {std::vector<std::string>{"--speed", "100001"},
                                          {"--speed", "-3"},
                                          {"--preset", "611"},
                                          {"--noise-density-dps-rthz", "-1"},
                                          // old names, hidden from --help, still work
                                          {"--noise-density", "-1"},
                                          {"--package-tau-spread", "-1"},
                                          {"--package-tau-spread-frac", "-1"},
                                          {"--effect", "warmup"},
                                          {"--mode", "fast"},
                                          {"--profile", "-10,abc"},
                                          {"--units", "0"},
                                          {"--no-such-option"},
                                          {"--temp-v-per-c", "0"},
                                          {"--sensor-ids", "S01,S01"},
                                          {"--effect", "supply=5"},
                                          {"--speed", "fast"},
                                          {"--max-msgs-per-s", "-1"},
                                          {"--truth-out", "/nonexistent/t.json"}}) {
        std::vector<std::string> argv = {GYROCAL_SIM_RIG_EXE, "--lcm-url",
                                         "udpm://239.255.76.67:7721?ttl=0"};
        argv.insert(argv.end(), args.begin(), args.end());
        const std::string err = dir + "/sim_rig_bad.err";
        launch::ChildProcess p(argv, dir + "/sim_rig_bad.out", err);
        const auto st = p.Wait(std::chrono::seconds(10));
        ASSERT_TRUE(st.has_value()) << args[0] << " did not exit";
        EXPECT_TRUE(st->exited && st->code == 2) << args[0] << ": " << st->Describe();
        std::ifstream e(err);
        std::string line;
        std::getline(e, line);
        EXPECT_NE(line.find(args[0]), std::string::npos) << "error names the option: " << line;
    }
}

}  // namespace
}  // namespace gyrocal
