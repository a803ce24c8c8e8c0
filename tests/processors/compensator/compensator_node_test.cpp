// gyrocal-compensator's node in one process over memq:// (LCM's in-process provider): samples
// before any set are not published; after a COEFFS_ set the RATE_ values are the truth; a set
// with an unknown term is refused and the old set stays in force; NaN, backwards and
// mislabelled samples are refused and counted. The real process over UDP multicast is
// compensator_process_test.cpp.
#include "processors/compensator/node/compensator_node.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/rate_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "processors/model/convert.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/processors/compensator/coeff_set_fixture.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
constexpr int64_t kStartUtime = testing::kCompensatorStartUtime;

coeff_set_t Set(int64_t id) { return testing::KnownSet(id, "run-memq"); }

// A sample of S01 turning at `rate_dps`, its gyro_v made from the set's own models (the truth).
gyro_sample_t Sample(int64_t seq, double temp_c, double rate_dps) {
    return testing::KnownSample(seq, temp_c, rate_dps);
}

struct MemqCompensator {
    compensator::node::CompensatorNode node;
    std::vector<rate_t> rates;
    explicit MemqCompensator(compensator::node::CompensatorNodeOptions o)
        : node((o.lcm_url = "memq://", o)) {
        testing::CollectInto(node.bus(), channels::AllSensors(channels::kRatePrefix), rates);
    }
    // Dispatches until the queue is empty (what a handler publishes is dispatched too), the
    // node's rates flushed after each message as its run loop does.
    void Drain() {
        for (int i = 0; i < 100000 && node.HandleFor(0); ++i) {
        }
    }
};

TEST(CompensatorNode, RatesAreTheTruthAndBadInputIsRefused) {
    MemqCompensator c(compensator::node::CompensatorNodeOptions::Defaults());
    bus::Bus& bus = c.node.bus();
    // GIVEN samples before any coefficient set: not published
    int64_t seq = 0;
    for (; seq < 5; ++seq) bus.Publish(channels::Gyro("S01"), Sample(seq, 20.0, 10.0));
    c.Drain();
    EXPECT_TRUE(c.rates.empty());
    // WHEN a set arrives, then samples at 10 deg/s from -5 to 55 degC (inside the valid range)
    bus.Publish(channels::Coeffs("S01"), Set(777));
    for (; seq < 105; ++seq)
        bus.Publish(channels::Gyro("S01"), Sample(seq, -5.0 + 0.6 * (seq - 5), 10.0));
    // a set with an unknown term: refused, the old one stays
    coeff_set_t bad = Set(888);
    bad.offset.term_names[2] = "dT^9";
    bus.Publish(channels::Coeffs("S01"), bad);
    for (; seq < 110; ++seq) bus.Publish(channels::Gyro("S01"), Sample(seq, 30.0, 10.0));
    // bad samples: NaN gyro_v, a timestamp going backwards, a sensor_id that is not the channel's
    gyro_sample_t nan_sample = Sample(seq++, 25.0, 0.0);
    nan_sample.gyro_v = NAN;
    bus.Publish(channels::Gyro("S01"), nan_sample);
    bus.Publish(channels::Gyro("S01"), Sample(3, 25.0, 0.0));
    gyro_sample_t stray = Sample(seq++, 25.0, 0.0);
    stray.sensor_id = "S02";
    bus.Publish(channels::Gyro("S01"), stray);
    c.Drain();
    // THEN rate = truth to rounding (gyro_v is built from the same models: 1e-9 deg/s is ~1e-11 V
    // at 6 mV/dps, far above double rounding of a 2.5 V sum), and the angle is the exact integral
    // of a constant 10 deg/s
    ASSERT_EQ(c.rates.size(), 105u);
    for (const rate_t& r : c.rates) {
        EXPECT_EQ(r.coeff_set_id, 777);
        EXPECT_NEAR(r.rate_dps, 10.0, 1e-9) << r.seq;
        EXPECT_EQ(r.range_flag, 0) << r.temp_c;
        const double elapsed_s = 1e-6 * static_cast<double>(r.utime - (kStartUtime + 5 * 10'000));
        EXPECT_NEAR(r.angle_deg, 10.0 * elapsed_s, 1e-9) << r.seq;
    }
    EXPECT_EQ(c.node.status().rejected(), 4);  // the bad set and the three bad samples
}

TEST(CompensatorNode, OtherSensorsAreIgnoredWhenSensorsAreChosen) {
    auto o = compensator::node::CompensatorNodeOptions::Defaults();
    o.sensors = {"S02"};
    MemqCompensator c(o);
    c.node.bus().Publish(channels::Coeffs("S01"), Set(5));
    for (int64_t seq = 0; seq < 10; ++seq)
        c.node.bus().Publish(channels::Gyro("S01"), Sample(seq, 25.0, 1.0));
    c.Drain();
    EXPECT_TRUE(c.rates.empty());
}

}  // namespace
}  // namespace gyrocal
