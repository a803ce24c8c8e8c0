// gyrocal-fitter --mode ramp's node (RampFitterNode) in one process over memq:// (LCM's
// in-process provider): the ramp of ramp_fitter_test.cpp (a unit taken 25 -> -15 -> 55 -> 25 degC
// at 1 degC/min with known offset and sensitivity curves and white noise, the table still, a
// sensitivity point of each direction every 300 s) as messages on the node's own bus, then the
// run's stop. Known truth: the curves; the final COEFFS_U1 is the stop event's set, and at every
// 5 degC of its range it is within 4 of its own standard uncertainties of the truth (white noise
// alone: the fit's covariance is its honest spread). Bounded waits on conditions, no sleep: the
// fit runs on the node's worker thread and the test handles the bus until the set is there.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "processors/fitter/node/fitter_node.hpp"
#include "processors/model/convert.hpp"
#include "processors/model/inputs.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/lcmtypes/message_builders.hpp"
#include "tests/processors/fitter/memq_fitter.hpp"
#include "tests/processors/fitter/ramp_truth.hpp"

namespace gyrocal {
namespace {

constexpr int64_t kT0 = 1'000'000'000'000'000;  // [us]

TEST(RampFitterNode, TheFinalSetOfARampIsTheTruthWithinItsStatedUncertainty) {
    fitter::node::FitterOptions o = fitter::node::FitterOptions::Defaults();
    o.mode = "ramp";
    o.ramp.refit_interval_s = 1800.0;
    o.ramp.min_span_s = 3600.0;
    testing::MemqFitter<fitter::node::RampFitterNode> fitter(o);
    auto& [node, bus, sets, reports] = fitter;
    auto drain = [&] {
        while (bus.Handle(std::chrono::milliseconds(0))) {
        }
        node.HandleFor(0);
    };
    run_event_t start = testing::RunEvent("R1", "start", {"U1"});
    start.utime = kT0;
    bus.Publish(std::string(channels::kRunEvent), start);

    // GIVEN the ramp (ramp_truth.hpp, as ramp_fitter_test.cpp feeds it), as messages
    int64_t u = kT0;
    testing::FeedRamp(
        [&](const testing::RampSample& s) {
            u = kT0 + s.t_us;
            gyro_sample_t g = testing::GyroSample("U1", u, s.seq, s.gyro_v, s.temp_c);
            g.supply_v = 5.0;
            bus.Publish(channels::Gyro("U1"), g);
        },
        [&](int64_t, int64_t count) {
            bus.Publish(std::string(channels::kEncoder), testing::TableEncoder(u, count, 0, 10000));
        },
        [&](const testing::RampPoint& r) {
            sensitivity_point_t p{};
            p.utime = u;
            p.sensor_id = "U1";
            p.run_id = "R1";
            p.rotation_id = r.rotation_id;
            p.start_utime = u;
            p.end_utime = u;
            p.direction = static_cast<int8_t>(r.direction);
            p.temp_c = r.temp_c;
            p.sensitivity_v_per_dps = r.sensitivity_v_per_dps;
            p.sensitivity_stderr_v_per_dps = testing::kRampSensSeV;
            p.accepted = true;
            bus.Publish(channels::Sensitivity("U1"), p);
        },
        [&](int64_t count, int64_t) {
            if (count % 1000 == 0) drain();
        });
    // WHEN the run stops
    run_event_t stop = testing::RunEvent("R1", "stop", {"U1"});
    stop.utime = u + 1'000'000;
    bus.Publish(std::string(channels::kRunEvent), stop);
    auto final_set = [&] {
        for (const fit_report_t& r : reports)
            if (r.is_final) return true;
        return false;
    };
    ASSERT_TRUE(testing::HandleUntil(
        bus,
        [&] {
            node.HandleFor(0);
            return final_set();
        },
        std::chrono::seconds(120), std::chrono::milliseconds(20)))
        << reports.size() << " reports, none final";
    // THEN the final report is complete, its set the stop event's
    const fit_report_t& r = reports.back();
    ASSERT_TRUE(r.is_final);
    EXPECT_EQ(r.status, "complete") << r.reason;
    EXPECT_EQ(r.coeff_set_id, stop.utime);
    ASSERT_FALSE(sets.empty());
    const coeff_set_t& msg = sets.back();
    EXPECT_EQ(msg.coeff_set_id, stop.utime);
    EXPECT_EQ(msg.num_rotations, 2 * 28);  // one pair per 300 s of 8400 s
    const model::CoeffSet set = model::FromMsg(msg);
    EXPECT_EQ(set.offset.method, "ramp");
    // The range the fit saw (its bin means: just inside -15..55).
    EXPECT_NEAR(set.offset.temp_min_c, -15.0, 0.2);
    EXPECT_NEAR(set.offset.temp_max_c, 55.0, 0.2);
    testing::ExpectTheRampTruth(set);
}

}  // namespace
}  // namespace gyrocal
