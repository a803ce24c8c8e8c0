#pragma once
// What gyrocal-plateau must do, told once for its node in-process (plateau_node_test.cpp) and
// for the real process over UDP (plateau_process_test.cpp): synthetic GYRO_S01/S02, ENCODER (one
// move), CHAMBER_STATE and RUN_EVENT in; PLATEAU_*, STABILITY_* and STATUS out; bad input counted,
// never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/plateau_state_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/bus/sample_guards.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/lcmtypes/bus/wire.hpp"
#include "tests/lcmtypes/message_builders.hpp"

namespace gyrocal::testing {

inline constexpr int64_t kPlateauT0 = 1'000'000'000'000'000;

// The node's options as the scenario needs them (the process test passes the same as flags):
// short windows so that 20 s of data hold a whole plateau: window 5 s, stable 2 s, average 5 s;
// only S01 and S02 accepted. Over a 5 s window the slope's standard error is
// sigma*sqrt(12)/(W sqrt(n)) = 0.05*3.46/(5*22.4) degC/s = 0.093 degC/min, so the slope
// threshold is raised to 1 degC/min (> 10 SE) for a flat trace to pass.
inline const std::vector<std::string> kPlateauScenarioFlags = {
    "--window-s",  "5",       "--min-stable-s",        "2",
    "--average-s", "5",       "--slope-max-c-per-min", "1",
    "--sensors",   "S01,S02", "--motion-guard-s",      "0.5"};

// The same values for the node in-process (kept beside the flags so the two cannot differ).
template <class Options>
void ApplyPlateauScenarioOptions(Options& o) {
    o.detector.window_s = 5;
    o.detector.min_stable_s = 2;
    o.detector.average_s = 5;
    o.detector.slope_max_c_per_min = 1;
    o.sensors = {"S01", "S02"};
    o.motion_guard_s = 0.5;
}

// Runs the scenario on `bus` (the node's or the test's), reaching the node through `wire`.
// `status` watches the node's STATUS on that bus.
inline void PlateauScenario(bus::Bus& bus, const Wire& wire, const StatusWatch& status) {
    std::map<std::string, plateau_t> plateaus;
    std::map<std::string, std::vector<std::string>> states;
    bus.Subscribe<plateau_t>(
        channels::AllSensors(channels::kPlateauPrefix),
        [&](const plateau_t& m, const std::string&) { plateaus[m.sensor_id] = m; });
    bus.Subscribe<plateau_state_t>(channels::AllSensors(channels::kStabilityPrefix),
                                   [&](const plateau_state_t& m, const std::string&) {
                                       auto& v = states[m.sensor_id];
                                       if (v.empty() || v.back() != m.state) v.push_back(m.state);
                                   });
    // Bad input first: a wrong type on GYRO_X, an unknown sensor, a NaN sample.
    PublishBadSamples(bus, kPlateauT0, "S99", "S01", &gyro_sample_t::temp_c);
    // A malformed RUN_EVENT: a negative array length makes LCM's decode throw.
    run_event_t malformed;
    malformed.utime = kPlateauT0;
    malformed.event = "start";
    malformed.num_sensors = -1;
    bus.Publish(std::string(channels::kRunEvent), malformed);
    run_event_t start = RunEvent("run-mp", "start", {});
    start.utime = kPlateauT0;
    bus.Publish(std::string(channels::kRunEvent), start);

    // 20 s of data at 100 Hz: two sensors flat at 30 degC (sigma 0.05 degC, gyro 2 mV), the
    // encoder at rest except a 90 deg move from 9 s to 10 s.
    const double sigma_t = 0.05, sigma_g = 2e-3;
    std::mt19937_64 rng(17);
    std::normal_distribution<double> g(0, 1);
    for (int k = 1; k <= 2000; ++k) {
        const int64_t utime = kPlateauT0 + k * 10'000;
        const double t = k * 0.01;
        if (k % 100 == 1) {
            chamber_state_t cs = Chamber(k / 100);
            cs.utime = utime;
            cs.setpoint_c = cs.air_c = 30;
            bus.Publish(std::string(channels::kChamberState), cs);
        }
        const int64_t counts = t < 9 ? 0 : t < 10 ? static_cast<int64_t>((t - 9) * 36000) : 36000;
        bus.Publish(std::string(channels::kEncoder), TableEncoder(utime, k, counts, 144000));
        for (const char* id : {"S01", "S02"}) {
            const double temp_c = 30 + sigma_t * g(rng);
            const double gyro_v = 2.505 + sigma_g * g(rng) + (t >= 9 && t < 10 ? 0.5 : 0.0);
            gyro_sample_t s = GyroSample(id, utime, k, gyro_v, temp_c);
            s.supply_v = 5.0;
            bus.Publish(channels::Gyro(id), s);
        }
        if (k % 20 == 0) wire.pace();
    }
    auto both_done = [&] {
        return plateaus.size() == 2 && states["S01"].back() == "done" &&
               states["S02"].back() == "done";
    };
    ASSERT_TRUE(wire.until(both_done, std::chrono::seconds(10)))
        << "plateaus received: " << plateaus.size()
        << ", S01 states: " << ::testing::PrintToString(states["S01"]);
    for (const auto& [id, p] : plateaus) {
        SCOPED_TRACE(id);
        EXPECT_EQ(p.run_id, "run-mp");
        EXPECT_EQ(p.setpoint_c, 30);
        EXPECT_EQ(p.plateau_id, p.start_utime);
        EXPECT_GT(p.n_samples, 490);
        // The move (9-10 s, +-0.5 s guard) fell inside the averaging window and was excluded:
        // 200 samples, so the 0.5 V rotation output does not reach the mean.
        EXPECT_EQ(p.n_excluded_motion, 200);
        EXPECT_EQ(p.seq_gaps, 0);
        // Means within 4 sigma/sqrt(n) of the truth (white noise).
        EXPECT_NEAR(p.temp_mean_c, 30, 4 * sigma_t / std::sqrt(p.n_samples));
        EXPECT_NEAR(p.gyro_mean_v, 2.505, 4 * sigma_g / std::sqrt(p.n_samples));
        EXPECT_DOUBLE_EQ(p.supply_mean_v, 5.0);
        EXPECT_EQ(states[id],
                  (std::vector<std::string>{"waiting", "settling", "averaging", "done"}));
    }
    EXPECT_EQ(plateaus.count("S99"), 0u);
    // An out-of-order sample (utime earlier than the newest of S01) is refused too. STATUS
    // counts two decode errors (the wrong type, and the malformed run event whose array length
    // the bus refuses), the three refusals (unknown sensor, NaN, out of order), and shows each
    // sensor's state (3 = done).
    EXPECT_TRUE(LateSampleIsRefused(bus, wire, status, "S01", kPlateauT0 + 5'000'000, 500, [&] {
        return status.last.decode_errors >= 2 && status.last.rejected >= 3 &&
               status.Extra("S01.state") == 3 && status.Extra("S02.state") == 3;
    }));
}

}  // namespace gyrocal::testing
