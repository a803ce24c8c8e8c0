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
#include <random>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "processors/fitter/fitter_node.hpp"
#include "processors/model/convert.hpp"
#include "processors/model/inputs.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/lcmtypes/message_builders.hpp"

namespace gyrocal {
namespace {

constexpr int64_t kT0 = 1'000'000'000'000'000;  // [us]
constexpr double kNoiseV = 1e-3;                // [V] white noise per sample
constexpr double kSensSeV = 5e-6;               // [V/(deg/s)] standard error of a point
constexpr double kHz = 10.0;                    // samples per second

double OffsetTrue(double t_c) {
    const double d = t_c - 25.0;
    return 2.5 + 5e-4 * d - 3e-6 * d * d;
}
double SensTrue(double t_c) { return 5e-3 + 2e-6 * (t_c - 25.0); }

TEST(RampFitterNode, TheFinalSetOfARampIsTheTruthWithinItsStatedUncertainty) {
    FitterOptions o = FitterOptions::Defaults();
    o.lcm_url = "memq://";
    o.mode = "ramp";
    o.ramp.refit_interval_s = 1800.0;
    o.ramp.min_span_s = 3600.0;
    RampFitterNode node(o);
    bus::Bus& bus = node.bus();
    std::vector<coeff_set_t> sets;
    std::vector<fit_report_t> reports;
    testing::CollectInto(bus, channels::Coeffs("U1"), sets);
    testing::CollectInto(bus, channels::Fit("U1"), reports);
    auto drain = [&] {
        while (bus.Handle(std::chrono::milliseconds(0))) {
        }
        node.HandleFor(0);
    };
    run_event_t start = testing::RunEvent("R1", "start", {"U1"});
    start.utime = kT0;
    bus.Publish(std::string(channels::kRunEvent), start);

    // GIVEN the ramp (the generator of ramp_fitter_test.cpp, as messages)
    std::mt19937_64 rng(42);
    std::normal_distribution<double> n(0.0, 1.0);
    const double rate = 1.0 / 60.0;
    const double legs[] = {40.0 / rate, 70.0 / rate, 30.0 / rate};
    double t_c = 25.0, t_s = 0.0;
    int64_t seq = 0, rot = 0, u = kT0;
    for (int leg = 0; leg < 3; ++leg) {
        const double dir = leg == 1 ? 1.0 : -1.0;
        for (double s = 0; s < legs[leg]; s += 1.0 / kHz, t_s += 1.0 / kHz) {
            t_c += dir * rate / kHz;
            u = kT0 + static_cast<int64_t>(std::llround(t_s * 1e6));
            gyro_sample_t g =
                testing::GyroSample("U1", u, seq++, OffsetTrue(t_c) + kNoiseV * n(rng), t_c);
            g.supply_v = 5.0;
            bus.Publish(channels::Gyro("U1"), g);
            if (seq % static_cast<int64_t>(kHz) == 0)
                bus.Publish(std::string(channels::kEncoder),
                            testing::TableEncoder(u, seq, 0, 10000));
            if (seq % static_cast<int64_t>(300 * kHz) == 0) {
                for (int d : {1, -1}) {
                    sensitivity_point_t p{};
                    p.utime = u;
                    p.sensor_id = "U1";
                    p.run_id = "R1";
                    p.rotation_id = ++rot;
                    p.start_utime = u;
                    p.end_utime = u;
                    p.direction = static_cast<int8_t>(d);
                    p.temp_c = t_c;
                    p.sensitivity_v_per_dps = SensTrue(t_c) + kSensSeV * n(rng);
                    p.sensitivity_stderr_v_per_dps = kSensSeV;
                    p.accepted = true;
                    bus.Publish(channels::Sensitivity("U1"), p);
                }
            }
            if (seq % 1000 == 0) drain();
        }
    }
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
    for (double tc = set.offset.temp_min_c; tc <= set.offset.temp_max_c; tc += 5.0) {
        const auto off = model::Evaluate(set.offset, model::SteadyStateInputs(set.offset, tc),
                                         model::RangePolicy::kClip);
        EXPECT_NEAR(off.value, OffsetTrue(tc), 4.0 * std::sqrt(off.variance)) << tc << " C";
        const auto sens =
            model::Evaluate(set.sensitivity, model::SteadyStateInputs(set.sensitivity, tc),
                            model::RangePolicy::kClip);
        EXPECT_NEAR(sens.value, SensTrue(tc), 4.0 * std::sqrt(sens.variance)) << tc << " C";
    }
}

}  // namespace
}  // namespace gyrocal
