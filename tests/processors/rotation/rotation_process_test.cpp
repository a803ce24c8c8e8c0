// gyrocal-rotation as a real OS process over UDP multicast (port 7741): the test publishes a
// synthetic gyro (S01) and encoder with a +90 and a -90 deg move, and receives SENSITIVITY_S01.
// Includes bad input that must be counted in STATUS while the process keeps working.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <thread>
#include <vector>

#include "bus/bus.hpp"
#include "bus/channels.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "launch/child_process.hpp"
#include "sample_guards.hpp"
#include "status_watch.hpp"
#include "synthetic_rotation.hpp"

namespace gyrocal {
namespace {

constexpr const char* kUrl = "udpm://239.255.76.67:7741?ttl=0&recv_buf_size=4194304";

bool WaitFor(Bus& bus, const std::function<bool()>& done, std::chrono::milliseconds limit) {
    return gyrocal::testing::HandleUntil(bus, done, limit, std::chrono::milliseconds(20));
}

TEST(RotationProcess, PublishesOnePointPerMoveAndCountsBadInput) {
    Bus bus(BusOptions{kUrl});
    std::vector<sensitivity_point_t> points;
    testing::CollectInto(bus, channels::AllSensors(channels::kSensitivityPrefix), points);
    testing::StatusWatch status(bus, "gyrocal-rotation");
    const auto dir = std::filesystem::temp_directory_path() /
                     ("gyrocal_rotation_mp_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    ChildProcess child({GYROCAL_ROTATION_BIN, "--lcm-url", kUrl, "--sensors", "S01"},
                       (dir / "stdout.txt").string(), (dir / "stderr.txt").string());
    ASSERT_TRUE(WaitFor(
        bus, [&] { return status.seen; }, std::chrono::seconds(10)))
        << "no STATUS from gyrocal-rotation";

    // Bad input: a wrong type on GYRO_X (decode error), an unknown sensor, a NaN sample.
    testing::PublishBadSamples(bus, rotation::testing::kT0Utime - 1000, "S07", "S01",
                               &gyro_sample_t::gyro_v);

    run_event_t start = testing::RunEvent("run-rot", "start", {});
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
                        testing::GyroSample("S01", e.utime, e.seq, e.gyro_v, e.temp_c));
        } else {
            bus.Publish(std::string(channels::kEncoder),
                        testing::TableEncoder(e.utime, e.seq, e.counts, spec.counts_per_rev));
        }
        if (++sent % 40 == 0) {  // pace: ~40 messages per 2 ms
            bus.Handle(std::chrono::milliseconds(0));
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
    }
    ASSERT_TRUE(WaitFor(
        bus, [&] { return points.size() >= 2; }, std::chrono::seconds(10)))
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
    // decode error, the three refusals (unknown sensor, NaN, out of order; the heartbeat comes
    // once a second) and the two accepted points.
    ASSERT_TRUE(testing::LateSampleIsRefused(
        bus, status, "S01", rotation::testing::kT0Utime + 1'000'000, 100, [&] {
            return status.last.decode_errors >= 1 && status.last.rejected >= 3 &&
                   status.Extra("points_accepted") == 2;
        }));
    const ExitStatus st = child.Stop();
    EXPECT_TRUE(st.exited && st.code == 0) << st.Describe();
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gyrocal
