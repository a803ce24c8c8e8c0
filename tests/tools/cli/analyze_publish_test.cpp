// `gyrocal analyze --publish` with the real gyrocal-compensator over udpm (port 7790): after the
// analysis stores its extended model and publishes it on COEFFS_S01, the compensator applies it
// and its RATE_S01 messages carry the stored set's coeff_set_id.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/rate_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "store/db/query.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/processors/analysis/run_db.hpp"
#include "tools/cli/cmd_analyze.hpp"

namespace gyrocal::analysis {
namespace {

namespace st = gyrocal::db;
using namespace std::chrono_literals;

constexpr const char* kUrl = "udpm://239.255.76.67:7790?ttl=0&recv_buf_size=4194304";

TEST(AnalyzePublish, LiveCompensatorAppliesThePublishedExtendedModel) {
    const std::string db = testing::WriteRunDb("publish.db");
    const std::string log = (std::filesystem::temp_directory_path() /
                             ("gyrocal_analysis_publish_" + std::to_string(::getpid()) + ".log"))
                                .string();
    launch::ChildProcess comp({GYROCAL_COMPENSATOR_EXE, "--lcm-url", kUrl}, log, log);

    bus::Bus bus(bus::BusOptions{kUrl});
    gyrocal::testing::StatusWatch status(bus, "gyrocal-compensator");
    int64_t last_set_id = -2;
    int n_rates = 0;
    bus.Subscribe<rate_t>(channels::Rate("S01"), [&](const rate_t& m, const std::string&) {
        last_set_id = m.coeff_set_id;
        ++n_rates;
    });
    // GYRO_S01 in message time: 10 samples per simulated second on a slow warming ramp, so the
    // extended model's "heating" input is known to the compensator (its dT/dt estimator needs
    // half of its 10 s window and a slope above 1/600 degC/s; this ramp is 0.1 degC/s).
    ASSERT_TRUE(gyrocal::testing::HandleUntil(
        bus, [&] { return status.seen; }, 10s))
        << "no STATUS from gyrocal-compensator; log " << log;
    int64_t seq = 0;
    auto send = [&](int n) {
        for (int i = 0; i < n; ++i, ++seq) {
            gyro_sample_t g{};
            g.utime = 1'000'000'000'000'000 + seq * 100'000;
            g.sensor_id = "S01";
            g.seq = seq;
            g.temp_c = 20.0 + 0.01 * static_cast<double>(seq);
            g.temp_v = 2.5 + (g.temp_c - 25.0) * 0.009;
            g.gyro_v = 2.5;
            g.supply_v = NAN;
            g.gyro_counts = g.temp_counts = 0;
            g.supply_counts = -1;
            bus.Publish(channels::Gyro("S01"), g);
        }
    };
    send(100);  // the compensator has no coefficients yet: each counted, nothing published
    ASSERT_TRUE(gyrocal::testing::HandleUntil(
        bus, [&] { return status.Extra("uncompensated") >= 100; }, 10s))
        << "uncompensated " << status.Extra("uncompensated") << "; log " << log;
    EXPECT_EQ(n_rates, 0);

    cli::AnalyzeOptions o;
    o.run_id = "R1";
    o.db = db;
    o.publish = true;
    o.lcm_url = kUrl;
    std::ostringstream out, err;
    ASSERT_EQ(cli::RunAnalyze(o, out, err), 0) << err.str();
    EXPECT_NE(err.str().find("published coefficient set"), std::string::npos) << err.str();
    auto q = st::OpenForQuery(db);
    const st::RunDetail d = st::ShowRun(*q, "R1");
    ASSERT_EQ(d.coeff_sets.size(), 1u);
    const int64_t stored_id = d.coeff_sets[0].set.coeff_set_id;
    EXPECT_EQ(d.coeff_sets[0].set.source.rfind("analysis:", 0), 0u);

    // Samples until one comes back compensated with the published set (bounded).
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (last_set_id != stored_id && std::chrono::steady_clock::now() < deadline) {
        send(10);
        gyrocal::testing::HandleUntil(
            bus, [&] { return last_set_id == stored_id; }, 100ms, 20ms);
    }
    EXPECT_EQ(last_set_id, stored_id) << n_rates << " RATE_S01 messages; compensator log " << log;
    EXPECT_GT(n_rates, 0);

    const launch::ExitStatus ended = comp.Stop();
    EXPECT_TRUE(ended.exited && ended.code == 0) << ended.Describe();
    testing::RemoveRunDb(db);
    std::filesystem::remove(log);
}

TEST(AnalyzePublish, PublishWithoutStoringIsRefused) {
    cli::AnalyzeOptions o;
    o.run_id = "R1";
    o.db = "/nonexistent.db";
    o.publish = true;
    o.store = false;
    std::ostringstream out, err;
    EXPECT_EQ(cli::RunAnalyze(o, out, err), 2);
    EXPECT_NE(err.str().find("--no-store"), std::string::npos) << err.str();
}

}  // namespace
}  // namespace gyrocal::analysis
