// gyrocal-fitter as a real OS process over UDP multicast (port 7750, TTL 0): plateaus, rotations
// and RUN_EVENT in; COEFFS_<id> out with exactly the ids used and the right curves, FIT_<id>
// reports (complete or partial) beside them; bad input counted in STATUS; bad options exit 2.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <random>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "gyrocal/noise_t.hpp"
#include "gyrocal/plateau_t.hpp"
#include "gyrocal/run_event_t.hpp"
#include "gyrocal/sensitivity_point_t.hpp"
#include "gyrocal/status_t.hpp"
#include "lcmtypes/bus/bus.hpp"
#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/launch/child_process.hpp"
#include "processors/model/convert.hpp"
#include "tests/lcmtypes/bus/bus_wait.hpp"
#include "tests/lcmtypes/bus/flow_pacer.hpp"
#include "tests/lcmtypes/bus/status_watch.hpp"
#include "tests/processors/fitter/fitter_fixture.hpp"

namespace gyrocal {
namespace {

using namespace std::chrono_literals;
constexpr const char* kUrl = "udpm://239.255.76.67:7750?ttl=0&recv_buf_size=4194304";
constexpr int64_t kT0Utime = 1'000'000'000'000'000;

using testing::OffsetTruthV;

struct Listener {
    bus::Bus bus{bus::BusOptions{kUrl}};
    std::vector<coeff_set_t> coeffs;
    std::vector<fit_report_t> reports;
    testing::StatusWatch status{bus, "gyrocal-fitter"};
    testing::FlowPacer pacer{bus, "gyrocal-fitter"};
    Listener() {
        testing::CollectInto(bus, channels::AllSensors(channels::kFitPrefix), reports);
        testing::CollectInto(bus, channels::AllSensors(channels::kCoeffsPrefix), coeffs);
    }
    // Bounded wait for a condition, dispatching messages meanwhile.
    template <class F>
    bool WaitFor(F&& cond, std::chrono::milliseconds timeout = 10s) {
        return testing::HandleUntil(bus, std::forward<F>(cond), timeout);
    }
};

run_event_t Event(const std::string& what, int64_t utime) {
    return testing::FitterRunEvent("run-7750", what, utime, {"S01", "S02", "S03"});
}
plateau_t Plateau(const std::string& id, double temp_c, int64_t start_utime) {
    return testing::TruthPlateau("run-7750", id, temp_c, start_utime);
}
sensitivity_point_t Rotation(const std::string& id, double temp_c, int64_t start_utime, int dir,
                             bool accepted) {
    return testing::TruthRotation("run-7750", id, temp_c, start_utime, dir, accepted);
}

TEST(FitterProcess, PublishesCoeffsWithExactIdsAndRefusesBadInput) {
    Listener l;
    launch::ChildProcess fitter({GYROCAL_FITTER_EXE, "--lcm-url", kUrl}, "", "");
    // The fitter's first STATUS comes after it has subscribed: then it hears what we publish.
    ASSERT_TRUE(l.WaitFor([&] { return l.status.seen; })) << "no STATUS from gyrocal-fitter";

    l.bus.Publish(std::string(channels::kRunEvent), Event("start", kT0Utime));
    std::vector<int64_t> plateau_ids, rotation_ids;
    const double temps[] = {-10.0, 30.0, 60.0};
    int64_t t = kT0Utime + 1'000'000;
    for (double temp : temps) {
        const plateau_t p = Plateau("S01", temp, t);
        plateau_ids.push_back(p.plateau_id);
        l.bus.Publish(channels::Plateau("S01"), p);
        l.bus.Publish(channels::Plateau("S02"), Plateau("S02", temp, t));  // S02: no rotations
        t += 100'000'000;
        for (int dir : {+1, -1}) {
            const sensitivity_point_t r = Rotation("S01", temp + 0.05 * dir, t, dir, true);
            rotation_ids.push_back(r.rotation_id);
            l.bus.Publish(channels::Sensitivity("S01"), r);
            t += 10'000'000;
        }
        l.bus.Publish(channels::Sensitivity("S01"),
                      Rotation("S01", temp, t, +1, false));  // not accepted
        t += 10'000'000;
        // The fitter has handled this burst before the next (keeps the socket buffer short).
        ASSERT_TRUE(l.pacer.Sync()) << "gyrocal-fitter answered no flow mark";
    }
    // S03: five noisy plateaus (noise = the stated sem, 2e-5 V): the N-point path.
    std::mt19937_64 rng(3);
    std::normal_distribution<double> noise(0.0, 2e-5);
    std::vector<int64_t> s3_ids;
    for (double temp : {-10.0, 5.0, 25.0, 45.0, 60.0}) {
        plateau_t p = Plateau("S03", temp, t);
        p.gyro_mean_v += noise(rng);
        s3_ids.push_back(p.plateau_id);
        l.bus.Publish(channels::Plateau("S03"), p);
        t += 100'000'000;
    }
    // Bad input: a plateau whose sensor_id disagrees with its channel; one for a sensor the run
    // does not have; one with a NaN mean.
    l.bus.Publish(channels::Plateau("S01"), Plateau("S02", 45.0, t + 1));
    l.bus.Publish(channels::Plateau("S09"), Plateau("S09", 45.0, t + 2));
    plateau_t nan_plateau = Plateau("S01", 45.0, t + 3);
    nan_plateau.gyro_mean_v = NAN;
    l.bus.Publish(channels::Plateau("S01"), nan_plateau);
    noise_t bad_noise{};
    bad_noise.sensor_id = "S03";
    bad_noise.run_id = "run-7750";
    bad_noise.bias_instability_v = -1e-4;  // a negative noise level
    l.bus.Publish(channels::Noise("S03"), bad_noise);
    l.bus.Publish(std::string(channels::kRunEvent), Event("stop", t + 10));

    // After stop: the final set of each sensor (the last COEFFS_ per sensor).
    auto last_of = [&](const std::string& id) -> const coeff_set_t* {
        const coeff_set_t* last = nullptr;
        for (const auto& c : l.coeffs)
            if (c.sensor_id == id) last = &c;
        return last;
    };
    // Each complete set arrives twice: when its last input arrived, and again on RUN_EVENT stop.
    auto count = [&](const std::string& id, int plateaus, int rotations) {
        int n = 0;
        for (const auto& c : l.coeffs)
            n += c.sensor_id == id && c.num_plateaus == plateaus && c.num_rotations == rotations;
        return n;
    };
    ASSERT_TRUE(l.WaitFor([&] {
        return count("S01", 3, 6) >= 2 && count("S02", 3, 0) >= 2 && count("S03", 5, 0) >= 2 &&
               l.status.seen && l.status.last.rejected >= 4 && l.reports.size() >= 6;
    })) << "coeffs received: "
        << l.coeffs.size();
    EXPECT_EQ(count("S01", 3, 6), 2);
    EXPECT_EQ(count("S03", 5, 0), 2);

    const coeff_set_t& s1 = *last_of("S01");
    EXPECT_EQ(s1.run_id, "run-7750");
    EXPECT_EQ(s1.source, "fitter");
    EXPECT_EQ(s1.plateau_ids, plateau_ids);
    EXPECT_EQ(s1.rotation_ids, rotation_ids);  // the unaccepted ones are not among them
    // coeff_set_id = utime of the newest input used: mid-run the last accepted rotation's, for
    // the final set the stop event's.
    const int64_t newest = rotation_ids.back() + 5'000'000;
    int64_t first_id = 0;
    for (const auto& c : l.coeffs)
        if (c.sensor_id == "S01" && c.num_rotations == 6 && first_id == 0)
            first_id = c.coeff_set_id;
    EXPECT_EQ(first_id, newest);
    EXPECT_EQ(s1.coeff_set_id, t + 10);
    EXPECT_EQ(s1.utime, t + 10);
    // Each set has its report; the final ones say complete (S01: the seed's 3-point method for
    // the offset, rotations at three temperatures) or partial (S02, S03: no rotation, nominal
    // sensitivity) and name the slow noise's source and what the outlier test could do.
    std::map<std::string, fit_report_t> final_reports;
    for (const auto& r : l.reports)
        if (r.is_final) final_reports[r.sensor_id] = r;
    ASSERT_EQ(final_reports.size(), 3u);
    EXPECT_EQ(final_reports["S01"].status, "complete") << final_reports["S01"].reason;
    EXPECT_EQ(final_reports["S01"].coeff_set_id, s1.coeff_set_id);
    EXPECT_EQ(final_reports["S02"].status, "partial");
    EXPECT_NE(final_reports["S02"].reason.find("nominal"), std::string::npos);
    EXPECT_EQ(final_reports["S03"].status, "partial");
    EXPECT_NE(final_reports["S01"].offset_detail.find("cannot check"), std::string::npos);
    EXPECT_NE(final_reports["S03"].offset_detail.find("outliers: checked 5 points"),
              std::string::npos)
        << final_reports["S03"].offset_detail;
    EXPECT_NE(final_reports["S03"].slow_noise_source.find("none: no NOISE_S03"), std::string::npos)
        << final_reports["S03"].slow_noise_source;
    const model::CoeffSet set = model::FromMsg(s1);
    EXPECT_EQ(set.offset.method, "3point");
    EXPECT_DOUBLE_EQ(set.offset.t0_c, -10.0);  // the seed's T0: the first plateau's temperature
    EXPECT_EQ(set.sensitivity.method, "wls");
    // Noise-free quadratic truth: both fits reproduce it to rounding.
    testing::ExpectTheTruth(set);

    const model::CoeffSet set2 = model::FromMsg(*last_of("S02"));
    EXPECT_EQ(set2.sensitivity.method, "nominal");
    EXPECT_DOUBLE_EQ(set2.sensitivity.coeffs[0], 0.006);
    EXPECT_EQ(last_of("S02")->num_rotations, 0);

    // S03: wls over 5 points, reference at the rounded midpoint; the fitted curve agrees with the
    // truth within 4 standard deviations of its own reported uncertainty (phi' C phi) at every
    // calibration temperature: the covariance survived the wire.
    ASSERT_NE(last_of("S03"), nullptr);
    EXPECT_EQ(last_of("S03")->plateau_ids, s3_ids);
    const model::CoeffSet set3 = model::FromMsg(*last_of("S03"));
    EXPECT_EQ(set3.offset.method, "wls");
    EXPECT_EQ(set3.offset.t0_c, 25.0);
    EXPECT_EQ(set3.offset.n_points, 5);
    for (double temp : {-10.0, 5.0, 25.0, 45.0, 60.0}) {
        model::ModelInputs in;
        in.temp_c = temp;
        const model::Evaluation e = model::Evaluate(set3.offset, in, model::RangePolicy::kClip);
        EXPECT_NEAR(e.value, OffsetTruthV(temp), 4 * std::sqrt(e.variance)) << temp;
    }

    EXPECT_GE(l.status.last.rejected, 4);
    fitter.Signal(SIGTERM);
    const auto st = fitter.Wait(5s);
    ASSERT_TRUE(st.has_value());
    EXPECT_TRUE(st->exited);
    EXPECT_EQ(st->code, 0);
}

TEST(FitterProcess, BadOptionsExitTwo) {
    for (std::vector<std::string> argv :
         {std::vector<std::string>{GYROCAL_FITTER_EXE, "--method", "magic"},
          {GYROCAL_FITTER_EXE, "--max-degree", "7"},
          {GYROCAL_FITTER_EXE, "--nominal-sensitivity-v-per-dps", "-1"},
          {GYROCAL_FITTER_EXE, "--outlier-alpha", "2"},
          {GYROCAL_FITTER_EXE, "--pool-alpha", "0"},
          {GYROCAL_FITTER_EXE, "--plateau-slow-noise-dps", "11"},
          {GYROCAL_FITTER_EXE, "--mode", "spiral"},
          {GYROCAL_FITTER_EXE, "--mode", "ramp", "--refit-interval-s", "1"},
          {GYROCAL_FITTER_EXE, "--mode", "ramp", "--min-span-s", "-1"},
          {GYROCAL_FITTER_EXE, "--mode", "ramp", "--max-bins-per-unit", "10"},
          {GYROCAL_FITTER_EXE, "--carry-cubic", "maybe"},
          {GYROCAL_FITTER_EXE, "--no-such-option"}}) {
        launch::ChildProcess p(argv, "/dev/null", "/dev/null");
        const auto st = p.Wait(5s);
        ASSERT_TRUE(st.has_value()) << argv[1];
        EXPECT_TRUE(st->exited);
        EXPECT_EQ(st->code, 2) << argv[1];
    }
    launch::ChildProcess help({GYROCAL_FITTER_EXE, "--help"}, "/dev/null", "/dev/null");
    const auto st = help.Wait(5s);
    ASSERT_TRUE(st.has_value());
    EXPECT_EQ(st->code, 0);
}

}  // namespace
}  // namespace gyrocal
