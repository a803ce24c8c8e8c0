#pragma once
// What gyrocal-rotation must do, told once for its node in-process (rotation_node_test.cpp) and
// for the real process over UDP (rotation_process_test.cpp): a synthetic gyro (S01) and encoder
// with a +90 and a -90 deg move in; one SENSITIVITY_S01 per move out, within the noise of the
// truth; bad input counted in STATUS while the node keeps working.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/lcmtypes/bus/sample_guards.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/lcmtypes/bus/wire.hpp"
#include "tests/lcmtypes/message_builders.hpp"
#include "tests/processors/rotation/synthetic_rotation.hpp"

namespace gyrocal::testing {

// The node's sensors (the process test passes --sensors S01).
inline const std::vector<std::string> kRotationScenarioSensors = {"S01"};

inline void RotationScenario(bus::Bus& bus, const Wire& wire, const StatusWatch& status) {
    std::vector<sensitivity_point_t> points;
    CollectInto(bus, channels::AllSensors(channels::kSensitivityPrefix), points);
    // Bad input: a wrong type on GYRO_X (decode error), an unknown sensor, a NaN sample.
    PublishBadSamples(bus, rotation::testing::kT0Utime - 1000, "S07", "S01",
                      &gyro_sample_t::gyro_v);
    run_event_t start = RunEvent("run-rot", "start", {});
    start.utime = rotation::testing::kT0Utime;
    bus.Publish(std::string(channels::kRunEvent), start);

    // The synthetic rig with a 200 Hz encoder (fewer messages; start found within 5 ms).
    rotation::testing::RigSpec spec;
    spec.encoder_hz = 200;
    spec.seed = 42;
    const std::vector<rotation::testing::Move> moves{{5, 90}, {15, -90}};
    int sent = 0;
    for (const rotation::testing::Event& e : rotation::testing::Generate(spec, moves, 25)) {
        if (e.is_gyro) {
            bus.Publish(channels::Gyro("S01"),
                        GyroSample("S01", e.utime, e.seq, e.gyro_v, e.temp_c));
        } else {
            bus.Publish(std::string(channels::kEncoder),
                        TableEncoder(e.utime, e.seq, e.counts, spec.counts_per_rev));
        }
        if (++sent % 40 == 0) wire.pace();
    }
    ASSERT_TRUE(wire.until([&] { return points.size() >= 2; }, std::chrono::seconds(10)))
        << "points received: " << points.size();
    ASSERT_EQ(points.size(), 2u);
    const double sigma_s = rotation::testing::ExpectedSensitivityStderr(spec, 90, 0.5, 2.0);
    for (size_t i = 0; i < points.size(); ++i) {
        const sensitivity_point_t& p = points[i];
        SCOPED_TRACE(i);
        EXPECT_TRUE(p.accepted) << p.reject_reason;
        EXPECT_EQ(p.sensor_id, "S01");
        EXPECT_EQ(p.run_id, "run-rot");
        EXPECT_EQ(p.rotation_id, p.start_utime);
        EXPECT_EQ(p.direction, i == 0 ? 1 : -1);
        EXPECT_NEAR(p.encoder_angle_deg, moves[i].angle_deg, 360.0 / spec.counts_per_rev + 1e-12);
        // Within 4 sigma of the truth, sigma from the noise (see ExpectedSensitivityStderr).
        EXPECT_NEAR(p.sensitivity_v_per_dps, spec.sensitivity_v_per_dps, 4 * sigma_s);
    }
    // An out-of-order sample (earlier than the newest of S01) is refused too. STATUS: the
    // decode error, the three refusals (unknown sensor, NaN, out of order) and the two points.
    EXPECT_TRUE(LateSampleIsRefused(
        bus, wire, status, "S01", rotation::testing::kT0Utime + 1'000'000, 100, [&] {
            return status.last.decode_errors >= 1 && status.last.rejected >= 3 &&
                   status.Extra("points_accepted") == 2;
        }));
}

}  // namespace gyrocal::testing
