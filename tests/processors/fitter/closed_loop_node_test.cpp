// The fitter's closed loop in one process over memq:// (gyrocal-fitter --mode plateau, its
// default): a simulated plateau run with an undeclared supply effect (gyrocal_sim through the
// analysis' test fixture: raw samples, encoder with turns, power record, chamber air, the plateaus
// and rotations the detectors would have published) is published into the node's bus; at the stop
// the node publishes the plateau set and then, from its fit worker, the final set fitted on every
// still sample with the supply term, its report and its analysis. The fit worker itself
// (fit_worker.hpp): the node's thread never waits for a fit.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <vector>

#include "gyrocal/analysis_t.hpp"
#include "gyrocal/chamber_state_t.hpp"
#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/encoder_sample_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/gyro_sample_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/power_state_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "processors/fitter/node/fit_worker.hpp"
#include "processors/fitter/node/fitter_node.hpp"
#include "processors/model/convert.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/processors/analysis/sim_run.hpp"
#include "tests/processors/fitter/memq_fitter.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
constexpr const char* kRun = "run-closed-loop";

run_event_t Event(const std::string& what, int64_t utime) {
    run_event_t e{};
    e.utime = utime;
    e.run_id = kRun;
    e.event = what;
    e.num_sensors = 1;
    e.sensor_ids = {"S01"};
    return e;
}

// Every message of the run into `bus`, in time order, handling as it goes (memq queues them).
void PublishRun(bus::Bus& bus, fitter::node::FitterNode& node, const analysis::testing::SimRun& s) {
    struct Timed {
        int64_t utime;
        std::function<void()> send;
    };
    std::vector<Timed> all;
    for (const auto& g : s.raw)
        all.push_back({g.utime, [&bus, g] {
                           gyro_sample_t m{};
                           m.utime = g.utime, m.sensor_id = "S01", m.seq = g.seq,
                           m.gyro_v = g.gyro_v;
                           m.temp_c = g.temp_c, m.supply_v = g.supply_v;
                           bus.Publish(channels::Gyro("S01"), m);
                       }});
    int64_t seq = 0;
    for (const auto& e : s.encoder)
        all.push_back({e.utime, [&bus, e, &seq] {
                           encoder_sample_t m{};
                           m.utime = e.utime, m.encoder_id = "TABLE", m.seq = ++seq;
                           m.counts = e.counts, m.counts_per_rev = e.counts_per_rev;
                           bus.Publish(std::string(channels::kEncoder), m);
                       }});
    for (const auto& a : s.air)
        all.push_back({a.utime, [&bus, a] {
                           chamber_state_t m{};
                           m.utime = a.utime, m.air_c = a.air_c, m.setpoint_c = a.air_c;
                           bus.Publish(std::string(channels::kChamberState), m);
                       }});
    for (const auto& p : s.run.plateaus)
        all.push_back({p.end_utime, [&bus, p] {
                           plateau_t m{};
                           m.utime = p.end_utime, m.sensor_id = "S01", m.run_id = kRun;
                           m.plateau_id = p.plateau_id, m.setpoint_c = NAN;
                           m.start_utime = p.start_utime, m.end_utime = p.end_utime;
                           m.n_samples = static_cast<int32_t>(p.n_samples);
                           m.temp_mean_c = p.temp_mean_c, m.temp_sem_c = p.temp_sem_c;
                           m.gyro_mean_v = p.gyro_mean_v, m.gyro_sem_v = p.gyro_sem_v;
                           m.supply_mean_v = NAN;
                           bus.Publish(channels::Plateau("S01"), m);
                       }});
    for (const auto& r : s.run.sensitivities)
        all.push_back({r.utime, [&bus, r] {
                           sensitivity_point_t m{};
                           m.utime = r.utime, m.sensor_id = "S01", m.run_id = kRun;
                           m.rotation_id = r.rotation_id, m.temp_c = r.temp_c;
                           m.direction = static_cast<int8_t>(r.direction);
                           m.sensitivity_v_per_dps = r.sensitivity_v_per_dps;
                           m.sensitivity_stderr_v_per_dps = r.stderr_v_per_dps;
                           m.accepted = r.accepted;
                           bus.Publish(channels::Sensitivity("S01"), m);
                       }});
    std::stable_sort(all.begin(), all.end(),
                     [](const Timed& a, const Timed& b) { return a.utime < b.utime; });
    power_state_t on{};
    on.utime = s.power.front().utime, on.sensor_id = "S01",
    on.power_on_utime = s.power.front().power_on_utime;
    on.source = "rig";
    bus.Publish(channels::Power("S01"), on);
    bus.Publish(std::string(channels::kRunEvent), Event("start", all.front().utime - 1));
    for (size_t i = 0; i < all.size(); ++i) {
        all[i].send();
        if (i % 200 == 0) node.HandleFor(0);
    }
    bus.Publish(std::string(channels::kRunEvent), Event("stop", all.back().utime + 1));
}

TEST(ClosedLoopNode, TheFinalSetIsFittedOnEveryStillSampleWithTheEffectAfterThePlateauSet) {
    // GIVEN the rig with a supply effect the declared model lacks (0.05 V/V: discovery_test's size)
    analysis::testing::SimRunOptions so;
    so.seed = 21;
    sim::SetEffect(so.effects, "supply", 0.05);
    const analysis::testing::SimRun s = analysis::testing::MakeSimRun(so, true);
    testing::MemqFitter<> fitter;
    auto& [node, bus, coeffs, reports] = fitter;
    std::vector<analysis_t> analyses;
    testing::CollectInto(bus, channels::AllSensors(channels::kAnalysisPrefix), analyses);
    // WHEN the run is published and stops
    PublishRun(bus, node, s);
    const auto closed = [&] {
        return std::any_of(reports.begin(), reports.end(), [](const fit_report_t& r) {
            return r.is_final && r.source == model::kClosedLoopSource;
        });
    };
    const auto end = std::chrono::steady_clock::now() + 120s;
    while (!closed() && std::chrono::steady_clock::now() < end) node.HandleFor(50);
    ASSERT_TRUE(closed()) << "no final report of the closed loop within 120 s";
    for (int i = 0; i < 20; ++i) node.HandleFor(10);
    // THEN the plateau set came first, the closed loop's set last (the one a compensator applies)
    ASSERT_GE(coeffs.size(), 2u);
    const coeff_set_t& last = coeffs.back();
    EXPECT_EQ(last.source, model::kClosedLoopSource);
    const auto plateau = std::find_if(coeffs.rbegin(), coeffs.rend(), [](const coeff_set_t& c) {
        return c.source == model::kFitterSource;
    });
    ASSERT_NE(plateau, coeffs.rend()) << "the plateau set stays published beside it";
    EXPECT_EQ(plateau->coeff_set_id, last.coeff_set_id) << "both are the stop's final sets";
    EXPECT_FALSE(plateau->plateau_ids.empty());
    // AND the final set carries the supply term the data confirm, near the rig's 0.05 V/V (within
    // 5 of its own standard errors: the analysis' autocorrelation-robust covariance)
    const model::CoeffSet set = model::FromMsg(last);
    const auto& names = set.offset.term_names;
    const auto k = std::find(names.begin(), names.end(), "supply") - names.begin();
    ASSERT_LT(static_cast<size_t>(k), names.size()) << "terms: " << names.size();
    EXPECT_NEAR(set.offset.coeffs[k], 0.05, 5 * std::sqrt(set.offset.covariance(k, k)));
    EXPECT_EQ(set.offset.method, "analysis");
    // AND its analysis says so, with the error before and after on held-out data
    ASSERT_FALSE(analyses.empty());
    const analysis_t& a = analyses.back();
    EXPECT_TRUE(a.is_final);
    EXPECT_EQ(a.coeff_set_id, last.coeff_set_id);
    EXPECT_EQ(a.source, model::kClosedLoopSource);
    EXPECT_NE(a.headline.find("supply"), std::string::npos) << a.headline;
    EXPECT_LT(a.offset_rms_v_after, a.offset_rms_v_before);
    EXPECT_NE(a.result_json.find("residual_bins"), std::string::npos);
}

// A fit that blocks until released, so that a test can hold the worker busy: started says the
// fit is under way; its result carries the job's unit, time and finality.
struct BlockedFit {
    std::mutex mu;
    std::condition_variable cv;
    bool release = false, started = false;
    fitter::RampFitResult operator()(const fitter::FitJob& j) {
        std::unique_lock<std::mutex> lock(mu);
        started = true;
        cv.notify_all();
        cv.wait(lock, [&] { return release; });
        fitter::RampFitResult r;
        r.sensor_id = j.sensor_id;
        r.report.utime = j.utime;
        r.report.is_final = j.is_final;
        return r;
    }
    bool WaitStarted() {
        std::unique_lock<std::mutex> lock(mu);
        return cv.wait_for(lock, 10s, [&] { return started; });
    }
    void Release() {
        {
            std::lock_guard<std::mutex> lock(mu);
            release = true;
        }
        cv.notify_all();
    }
};

TEST(FitWorker, TheCallerNeverWaitsForAFitAndTakesItsResultLater) {
    // GIVEN a worker whose fit blocks until released
    BlockedFit fit;
    fitter::node::FitWorker w([&](const fitter::FitJob& j) { return fit(j); });
    fitter::FitJob job;
    job.sensor_id = "S01";
    // WHEN a job is submitted and the fit is under way
    w.Submit({job});
    ASSERT_TRUE(fit.WaitStarted());
    // THEN the caller goes on: nothing to take yet, one outstanding
    EXPECT_TRUE(w.Take().empty());
    EXPECT_EQ(w.outstanding(), 1u);
    EXPECT_FALSE(w.WaitIdle(10ms));
    // AND once the fit ends its result is there, with the wall time it took
    fit.Release();
    ASSERT_TRUE(w.WaitIdle(10s));
    const auto done = w.Take();
    ASSERT_EQ(done.size(), 1u);
    EXPECT_EQ(done[0].sensor_id, "S01");
    EXPECT_GT(done[0].fit_wall_s, 0.0);
    EXPECT_EQ(w.outstanding(), 0u);
}

TEST(FitWorker, AQueuedRefitIsSupersededByANewerJobOfItsUnit) {
    // GIVEN a worker whose first fit blocks until released, so that the rest queue behind it
    BlockedFit fit;
    fitter::node::FitWorker w([&](const fitter::FitJob& j) { return fit(j); });
    auto job = [](const char* id, int64_t utime, bool final) {
        fitter::FitJob j;
        j.sensor_id = id;
        j.run_id = "R1";
        j.utime = utime;
        j.is_final = final;
        return j;
    };
    w.Submit({job("S01", 1, false)});
    ASSERT_TRUE(fit.WaitStarted());
    // WHEN S01's refits keep coming while the first is under way, S02's beside them, then
    // S01's final
    w.Submit({job("S01", 2, false), job("S02", 2, false)});
    w.Submit({job("S01", 3, false)});
    w.Submit({job("S01", 4, true)});
    fit.Release();
    ASSERT_TRUE(w.WaitIdle(10s));
    // THEN the fit under way ends, S01's waiting refits gave way to its final (one job of S01
    // waited at a time), S02's refit ran, and the two skipped refits are counted
    const auto done = w.Take();
    ASSERT_EQ(done.size(), 3u);
    EXPECT_EQ(done[0].sensor_id, "S01");
    EXPECT_EQ(done[0].report.utime, 1);
    EXPECT_EQ(done[1].sensor_id, "S01");
    EXPECT_EQ(done[1].report.utime, 4);
    EXPECT_TRUE(done[1].report.is_final);
    EXPECT_EQ(done[2].sensor_id, "S02");
    EXPECT_EQ(w.superseded(), 2);
}

TEST(FitWorker, AFitThatThrowsIsAReportOfNoneWithTheReason) {
    fitter::node::FitWorker w([](const fitter::FitJob&) -> fitter::RampFitResult {
        throw std::runtime_error("broken bins");
    });
    fitter::FitJob job;
    job.sensor_id = "S02";
    job.is_final = true;
    w.Submit({job});
    ASSERT_TRUE(w.WaitIdle(10s));
    const auto done = w.Take();
    ASSERT_EQ(done.size(), 1u);
    EXPECT_EQ(done[0].report.status, "none");
    EXPECT_TRUE(done[0].report.is_final);
    EXPECT_NE(done[0].report.reason.find("broken bins"), std::string::npos);
}

}  // namespace
}  // namespace gyrocal
