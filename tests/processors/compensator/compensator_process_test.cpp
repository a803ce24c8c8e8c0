// gyrocal-compensator as a real OS process over UDP multicast (port 7751, TTL 0): samples before
// any set are counted uncompensated; after a COEFFS_ the RATE_ values are the truth (outside the
// valid range too under the default policy, extrapolate, flagged 2; clipped and flagged 1 under
// --out-of-range clip); a bad set is rejected, counted in STATUS, and the old set stays in force
// (each set is waited for in STATUS, never slept over); NaN, backwards and mislabelled samples
// are refused and counted; bad options exit 2.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/rate_t.hpp"
#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "processors/model/convert.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/processors/compensator/coeff_set_fixture.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
constexpr const char* kUrl = "udpm://239.255.76.67:7751?ttl=0&recv_buf_size=4194304";
constexpr int64_t kStartUtime = testing::kCompensatorStartUtime;

coeff_set_t Set(int64_t id) { return testing::KnownSet(id, "run-7751"); }

struct Listener {
    bus::Bus bus{bus::BusOptions{kUrl}};
    std::vector<rate_t> rates;
    testing::StatusWatch status{bus, "gyrocal-compensator"};
    Listener() { testing::CollectInto(bus, channels::AllSensors(channels::kRatePrefix), rates); }
    template <class F>
    bool WaitFor(F&& cond, std::chrono::milliseconds timeout = 10s) {
        return testing::HandleUntil(bus, std::forward<F>(cond), timeout);
    }
};

gyro_sample_t Sample(int64_t seq, double temp_c, double rate_dps) {
    return testing::KnownSample(seq, temp_c, rate_dps);
}

// One run of the process; `policy_args` empty = the default range policy (extrapolate).
void RatesFromCoeffsAndBadSetRejected(const std::vector<std::string>& policy_args) {
    const bool clip = !policy_args.empty() && policy_args.back() == "clip";
    Listener l;
    std::vector<std::string> argv = {GYROCAL_COMPENSATOR_EXE, "--lcm-url", kUrl};
    argv.insert(argv.end(), policy_args.begin(), policy_args.end());
    launch::ChildProcess comp(argv);
    ASSERT_TRUE(l.WaitFor([&] { return l.status.seen; })) << "no STATUS from gyrocal-compensator";

    // GIVEN samples before any coefficient set: not published, counted.
    int64_t seq = 0;
    for (; seq < 5; ++seq) l.bus.Publish(channels::Gyro("S01"), Sample(seq, 20.0, 10.0));
    // WHEN a set arrives, then samples at a constant 10 deg/s at temperatures across the range
    l.bus.Publish(channels::Coeffs("S01"), Set(777));
    // Its STATUS names the set in force before any sample is sent against it.
    ASSERT_TRUE(l.WaitFor([&] { return l.status.Extra("S01.coeff_set_id") == 777; }))
        << "STATUS never reported S01.coeff_set_id 777";
    const int64_t first_compensated = seq;
    for (; seq < 105; ++seq)
        l.bus.Publish(channels::Gyro("S01"), Sample(seq, -5.0 + 0.6 * (seq - 5), 10.0));
    // a bad set (unknown term): must be refused and the old one kept
    coeff_set_t bad = Set(888);
    bad.offset.term_names[2] = "dT^9";
    l.bus.Publish(channels::Coeffs("S01"), bad);
    ASSERT_TRUE(l.WaitFor([&] { return l.status.Extra("coeff_sets_rejected") >= 1; }))
        << "STATUS never counted the bad set";
    EXPECT_EQ(l.status.Extra("S01.coeff_set_id"), 777);  // the old set stays in force
    for (; seq < 110; ++seq)
        l.bus.Publish(channels::Gyro("S01"), Sample(seq, 70.0, 10.0));  // above the range
    // bad samples: NaN gyro_v, a timestamp going backwards, a sensor_id that is not the channel's
    gyro_sample_t nan_sample = Sample(seq++, 25.0, 0.0);
    nan_sample.gyro_v = NAN;
    l.bus.Publish(channels::Gyro("S01"), nan_sample);
    l.bus.Publish(channels::Gyro("S01"), Sample(3, 25.0, 0.0));
    gyro_sample_t stray = Sample(seq++, 25.0, 0.0);
    stray.sensor_id = "S02";
    l.bus.Publish(channels::Gyro("S01"), stray);

    ASSERT_TRUE(l.WaitFor([&] {
        return l.rates.size() >= 105 && l.status.Extra("coeff_sets_rejected") >= 1 &&
               l.status.Extra("uncompensated") >= 5 && l.status.last.rejected >= 4;
    })) << "rates "
        << l.rates.size() << ", rejected " << l.status.Extra("coeff_sets_rejected");
    // THEN rate = truth to rounding (the test builds gyro_v from the same models: 1e-9 deg/s is
    // ~1e-11 V / 6 mV/dps, far above double rounding of a 2.5 V sum), the angle is the trapezoid
    // integral of a constant rate (exact: 10 deg/s * elapsed), and the range flag marks 70 degC.
    ASSERT_EQ(l.rates.size(), 105u);
    for (const rate_t& r : l.rates) {
        EXPECT_EQ(r.coeff_set_id, 777);  // the bad set never took effect
        const double elapsed_s =
            1e-6 * static_cast<double>(r.utime - (kStartUtime + first_compensated * 10'000));
        const bool outside = r.temp_c < -10.0 || r.temp_c > 60.0;
        if (!outside) {
            EXPECT_NEAR(r.rate_dps, 10.0, 1e-9) << r.seq;
            EXPECT_EQ(r.range_flag, 0) << r.temp_c;
        } else if (clip) {
            EXPECT_EQ(r.range_flag, 1) << r.temp_c;  // clipped: evaluated at the nearest bound
            EXPECT_GT(std::abs(r.rate_dps - 10.0), 1e-3);  // the bound's value: not 10
        } else {
            // extrapolated: the test's samples continue the same polynomials, so the rate is
            // still the truth, and the flag says the sample was outside the calibrated range
            EXPECT_EQ(r.range_flag, 2) << r.temp_c;
            EXPECT_NEAR(r.rate_dps, 10.0, 1e-9) << r.seq;
        }
        if (!(clip && outside)) {  // a clipped rate is not 10, so neither is its angle
            EXPECT_NEAR(r.angle_deg, 10.0 * elapsed_s, 1e-9) << r.seq;
        }
    }
    EXPECT_EQ(l.status.last.rejected, 4);  // the bad set and the three bad samples, none published
    EXPECT_EQ(l.status.Extra("coeff_sets_applied"), 1.0);
    EXPECT_EQ(l.status.Extra("uncompensated"), 5.0);
    comp.Signal(SIGTERM);
    const auto st = comp.Wait(5s);
    ASSERT_TRUE(st.has_value());
    EXPECT_EQ(st->code, 0);
}

// Both policies on the same port, one after the other (one ctest entry: never in parallel).
TEST(CompensatorProcess, RatesFromCoeffsAndBadSetRejectedUnderBothRangePolicies) {
    {
        SCOPED_TRACE("default policy (extrapolate)");
        RatesFromCoeffsAndBadSetRejected({});
    }
    {
        SCOPED_TRACE("--out-of-range clip");
        RatesFromCoeffsAndBadSetRejected({"--out-of-range", "clip"});
    }
}

TEST(CompensatorProcess, HelpStatesTheDefaultRangePolicyAndWhy) {
    const std::string out_path = ::testing::TempDir() + "compensator_help.txt";
    launch::ChildProcess p({GYROCAL_COMPENSATOR_EXE, "--help"}, out_path, "/dev/null");
    const auto st = p.Wait(5s);
    ASSERT_TRUE(st.has_value());
    EXPECT_EQ(st->code, 0);
    std::ifstream f(out_path);
    const std::string help((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    EXPECT_NE(help.find("extrapolate (continue the fitted polynomial; default)"), std::string::npos)
        << help;
    EXPECT_NE(help.find("range_flag"), std::string::npos) << help;
    EXPECT_NE(help.find("Exit codes"), std::string::npos) << help;
}

TEST(CompensatorProcess, BadOptionsExitTwo) {
    for (std::vector<std::string> argv :
         {std::vector<std::string>{GYROCAL_COMPENSATOR_EXE, "--out-of-range", "wrap"},
          {GYROCAL_COMPENSATOR_EXE, "--out-of-range"},
          {GYROCAL_COMPENSATOR_EXE, "--sensor", "S 01"},
          {GYROCAL_COMPENSATOR_EXE, "--bogus"}}) {
        launch::ChildProcess p(argv, "/dev/null", "/dev/null");
        const auto st = p.Wait(5s);
        ASSERT_TRUE(st.has_value()) << argv[1];
        EXPECT_EQ(st->code, 2) << argv[1];
    }
}

}  // namespace
}  // namespace gyrocal
