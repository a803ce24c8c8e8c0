// A ramp calibration end to end, as separate OS processes over UDP multicast (TTL 0, this file's
// own ports 7960-7961): `gyrocal calibrate --profile ramp` starts the simulated rig, the detectors,
// the fitter in ramp mode, the compensator, the recorder and the sequencer's ramp procedure; the
// test checks the fitted curves against the rig's truth sidecar, and the early stop.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "lcmtypes/launch/child_process.hpp"
#include "processors/model/inputs.hpp"
#include "processors/model/model.hpp"
#include "tests/tools/cli/e2e_support.hpp"
#include "tests/tools/cli/stored_model.hpp"

namespace gyrocal {
namespace {

using nlohmann::json;

double Poly(const json& curve, double die_c) {
    const auto c = curve.at("coeffs").get<std::vector<double>>();
    const double d = die_c - curve.at("t0_c").get<double>();
    double v = 0, p = 1;
    for (double k : c) v += k * p, p *= d;
    return v;
}

struct Ran {
    std::string dir, printed;
    std::optional<launch::ExitStatus> ended;
};

// 2 units; the package lag shortened (40 s) so that the dwell at each waypoint can be short.
Ran RunRamp(const std::string& name, const std::string& url, std::vector<std::string> extra) {
    Ran r;
    r.dir = FreshDir("gyrocal_ramp_" + name);
    const std::string out = r.dir + "/calibrate.out";
    const std::vector<std::string> argv =
        Joined({{GYROCAL_CLI, "calibrate", "--profile", "ramp"},
                SimRunArgs("2", "7", "40", r.dir + "/run.db", url, r.dir + "/logs"),
                {"--rig-arg=--package-tau-s=40", "--wall-timeout-s", "500"},
                extra});
    launch::ChildProcess cal(argv, out, out);
    r.ended = cal.Wait(std::chrono::seconds(540));
    r.printed = launch::ReadLog(out);
    return r;
}

TEST(RampEndToEnd, FittedCurvesMatchTheRigTruthWithinTheNoise) {
    // Cool 25 -> 10, heat 10 -> 40, cool 40 -> 10 at 3 degC/min: every temperature of 10..40
    // is passed heating and cooling, turns every 120 s.
    const Ran r =
        RunRamp("truth", UdpmUrl(7960),
                {"--setpoints-c", "10,40,10", "--turn-interval-s", "120", "--dwell-s", "60"});
    ASSERT_TRUE(r.ended.has_value()) << "calibrate did not finish:\n" << r.printed;
    ASSERT_TRUE(r.ended->exited && r.ended->code == 0) << r.ended->Describe() << "\n" << r.printed;
    EXPECT_NE(r.printed.find("stop: completed"), std::string::npos) << r.printed;

    const json truth = json::parse(launch::ReadLog(r.dir + "/logs/truth.json"));
    Sql sql(r.dir + "/run.db");
    const std::string run =
        sql.Rows("SELECT run_id FROM runs WHERE run_id <> '' ORDER BY started_utime DESC")
            .at(0)
            .at(0);
    const double rate_c_per_s = 3.0 / 60.0;
    const double sensor_tau_s = truth.at("config").at("thermal").at("sensor_tau_s");
    for (const json& unit : truth.at("units")) {
        const std::string id = unit.at("sensor_id");
        SCOPED_TRACE(id);
        // Turns on the move: at least one pair per interval of the ~16 min of ramps, all accepted.
        EXPECT_GE(sql.Int("SELECT count(*) FROM sensitivity_points WHERE accepted=1 AND run_id='" +
                          run + "' AND sensor_id='" + id + "'"),
                  10);
        // Sets were published during the run as well as the final one.
        EXPECT_GE(sql.Int("SELECT count(*) FROM coeff_sets WHERE run_id='" + run +
                          "' AND sensor_id='" + id + "'"),
                  2);
        const std::string row = NewestCoeffRow(sql, run, id);
        ASSERT_FALSE(row.empty());
        const model::Model offset = StoredModel(sql, row, "offset");
        const model::Model sens = StoredModel(sql, row, "sensitivity");
        EXPECT_EQ(offset.method, "ramp");
        ASSERT_GE(offset.term_names.size(), 3u);
        EXPECT_LE(offset.temp_min_c, 13.0);
        EXPECT_GE(offset.temp_max_c, 37.0);
        const model::Evaluator off_eval(offset), sens_eval(sens);
        const double sensor_offset_c = unit.at("temp_sensor_offset_c");
        // The curves at steady state over the range the fit saw, against the truth at the die
        // temperature the reading stands for (reading = die + the unit's sensor offset).
        // Tolerance, derived:
        //  - statistical: 4 x the fit's own 1-sigma value uncertainty sqrt(phi' C phi), C the
        //    analysis' autocorrelation-robust covariance of the still bins (it carries the slow
        //    noise, bias instability and random walk, that the bins keep);
        //  - systematic, offset: when the rate term is not chosen, the reading lags the die by
        //    rate x sensor_tau on the ramps; heating and cooling through the same temperatures
        //    cancel it to first order, what is left is at most the lag times the unit's true
        //    offset slope there;
        //  - systematic, sensitivity: 0.1 % for the encoder's quantization of a 90 deg move
        //    (1 count of 10000 per rev) and the offset drift across a turn on the ramp.
        for (double t_c = offset.temp_min_c; t_c <= offset.temp_max_c; t_c += 2.5) {
            const double die_c = t_c - sensor_offset_c;
            const double slope_v_per_c = std::abs(Poly(unit.at("offset_v"), die_c + 0.5) -
                                                  Poly(unit.at("offset_v"), die_c - 0.5));
            const model::Evaluation o =
                off_eval.Evaluate(model::SteadyStateInputs(offset, t_c), model::RangePolicy::kClip);
            const double lag_v = slope_v_per_c * rate_c_per_s * sensor_tau_s;
            EXPECT_NEAR(o.value, Poly(unit.at("offset_v"), die_c),
                        4.0 * std::sqrt(o.variance) + lag_v)
                << "offset at " << t_c << " C";
            const model::Evaluation s =
                sens_eval.Evaluate(model::SteadyStateInputs(sens, t_c), model::RangePolicy::kClip);
            const double s_true = Poly(unit.at("sensitivity_v_per_dps"), die_c);
            EXPECT_NEAR(s.value, s_true, 4.0 * std::sqrt(s.variance) + 1e-3 * s_true)
                << "sensitivity at " << t_c << " C";
        }
    }
}

TEST(RampEndToEnd, StopsEarlyAtTheTargetAndSaysWhatItSaved) {
    // Targets a loose calibration reaches during the second leg; sets every 120 s of data once
    // 600 s are in, so the sequencer hears them on the way.
    const Ran r = RunRamp("early", UdpmUrl(7961),
                          {"--setpoints-c", "10,40,10", "--turn-interval-s", "120", "--dwell-s",
                           "60", "--target-offset-dps", "0.5", "--target-sensitivity-pct", "5",
                           "--fitter-arg=--refit-interval-s=120", "--fitter-arg=--min-span-s=600"});
    ASSERT_TRUE(r.ended.has_value()) << "calibrate did not finish:\n" << r.printed;
    ASSERT_TRUE(r.ended->exited && r.ended->code == 0) << r.ended->Describe() << "\n" << r.printed;
    EXPECT_NE(r.printed.find("stop: completed early: target reached"), std::string::npos)
        << r.printed;
    EXPECT_NE(r.printed.find("chamber time saved"), std::string::npos) << r.printed;
    // The plan: 15 + 30 + 30 degC at 3 degC/min plus three dwells is ~28 min; stopped early means
    // the last leg (30 degC, 10 min) was not finished.
    Sql sql(r.dir + "/run.db");
    const double span_s =
        1e-6 * static_cast<double>(sql.Int("SELECT max(utime) - min(utime) FROM run_events"));
    EXPECT_LT(span_s, 25 * 60.0);
}

TEST(RampEndToEnd, BadRampOptionsAreRefusedBeforeAnythingStarts) {
    struct Case {
        std::vector<std::string> args;
        std::string says;
    };
    const std::vector<Case> cases = {
        {{"--profile", "ramp", "--procedure", "rig"}, "--procedure sequencer"},
        {{"--profile", "ramp", "--ramp-range-c", "40,10"}, "--ramp-range-c"},
        {{"--profile", "five", "--target-offset-dps", "0.1"}, "only with --profile ramp"},
        {{"--profile", "ramp", "--turn-interval-s", "5"}, "--turn-interval-s"},
        {{"--profile", "ramp", "--target-sensitivity-pct", "-1"}, "--target-sensitivity-pct"},
    };
    const std::string dir = FreshDir("gyrocal_ramp_bad");
    for (const Case& c : cases) {
        std::vector<std::string> argv = {GYROCAL_CLI, "calibrate",
                                         "--db",      dir + "/x.db",
                                         "--lcm-url", "udpm://239.255.76.67:7961?ttl=0"};
        argv.insert(argv.end(), c.args.begin(), c.args.end());
        const std::string out = dir + "/out";
        launch::ChildProcess p(argv, out, out);
        const auto ended = p.Wait(std::chrono::seconds(60));
        ASSERT_TRUE(ended.has_value());
        EXPECT_TRUE(ended->exited && ended->code == 2)
            << ended->Describe() << " for " << c.args.back();
        EXPECT_NE(launch::ReadLog(out).find(c.says), std::string::npos) << launch::ReadLog(out);
    }
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.db")) << "nothing is created for bad options";
}

}  // namespace
}  // namespace gyrocal
