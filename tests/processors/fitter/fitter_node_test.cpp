// gyrocal-fitter's node (--mode plateau) in one process over memq:// (LCM's in-process provider):
// plateaus, rotations and RUN_EVENT published into the node's own bus give COEFFS_<id> with
// exactly the ids used and the truth's curves, and a FIT_<id> report; bad input is refused and
// counted. The real process over UDP multicast is fitter_process_test.cpp.
#include "processors/fitter/node/fitter_node.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "processors/model/convert.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/processors/fitter/fitter_fixture.hpp"
#include "tests/processors/fitter/memq_fitter.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
using testing::kT0Utime;  // the sim rig's default start
constexpr const char* kRun = "run-memq";

run_event_t Event(const std::string& what, int64_t utime) {
    return testing::FitterRunEvent(kRun, what, utime, {"S01"});
}
plateau_t Plateau(const std::string& id, double temp_c, int64_t start_utime) {
    return testing::TruthPlateau(kRun, id, temp_c, start_utime);
}
sensitivity_point_t Rotation(double temp_c, int64_t start_utime, int dir, bool accepted) {
    return testing::TruthRotation(kRun, "S01", temp_c, start_utime, dir, accepted);
}

TEST(FitterNode, FinalSetIsTheTruthWithExactIdsAndBadInputIsRefused) {
    testing::MemqFitter<> fitter;
    auto& [node, bus, coeffs, reports] = fitter;

    // GIVEN a run of S01 with plateaus at three temperatures, two accepted rotations at each and
    // one not accepted
    bus.Publish(std::string(channels::kRunEvent), Event("start", kT0Utime));
    std::vector<int64_t> plateau_ids, rotation_ids;
    int64_t t = kT0Utime + 1'000'000;
    for (double temp : {-10.0, 30.0, 60.0}) {
        const plateau_t p = Plateau("S01", temp, t);
        plateau_ids.push_back(p.plateau_id);
        bus.Publish(channels::Plateau("S01"), p);
        t += 100'000'000;
        for (int dir : {+1, -1}) {
            const sensitivity_point_t r = Rotation(temp + 0.05 * dir, t, dir, true);
            rotation_ids.push_back(r.rotation_id);
            bus.Publish(channels::Sensitivity("S01"), r);
            t += 10'000'000;
        }
        bus.Publish(channels::Sensitivity("S01"), Rotation(temp, t, +1, false));
        t += 10'000'000;
    }
    // and bad input: a plateau whose sensor_id is not its channel's, one of a sensor the run does
    // not have, one with a NaN mean
    bus.Publish(channels::Plateau("S01"), Plateau("S02", 45.0, t + 1));
    bus.Publish(channels::Plateau("S09"), Plateau("S09", 45.0, t + 2));
    plateau_t nan_plateau = Plateau("S01", 45.0, t + 3);
    nan_plateau.gyro_mean_v = NAN;
    bus.Publish(channels::Plateau("S01"), nan_plateau);
    // WHEN the run stops
    bus.Publish(std::string(channels::kRunEvent), Event("stop", t + 10));
    for (int i = 0; i < 10000 && bus.Handle(0ms); ++i) {
    }

    // THEN the final set used exactly the plateaus and the accepted rotations
    ASSERT_FALSE(coeffs.empty());
    const coeff_set_t& last = coeffs.back();
    EXPECT_EQ(last.sensor_id, "S01");
    EXPECT_EQ(last.run_id, kRun);
    EXPECT_EQ(last.plateau_ids, plateau_ids);
    EXPECT_EQ(last.rotation_ids, rotation_ids);
    EXPECT_EQ(last.coeff_set_id, t + 10);  // the stop event's utime: the newest input
    // Noise-free quadratic truth: both fits reproduce it to rounding.
    const model::CoeffSet set = model::FromMsg(last);
    testing::ExpectTheTruth(set);
    // a final report beside it, complete, naming the same set
    const fit_report_t* final_report = nullptr;
    for (const auto& r : reports)
        if (r.is_final && r.sensor_id == "S01") final_report = &r;
    ASSERT_NE(final_report, nullptr);
    EXPECT_EQ(final_report->status, "complete") << final_report->reason;
    EXPECT_EQ(final_report->coeff_set_id, last.coeff_set_id);
    // and the three bad plateaus refused and counted
    EXPECT_EQ(node.status().rejected(), 3);
}

}  // namespace
}  // namespace gyrocal
