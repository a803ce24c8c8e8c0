// Schema v5: the fitter's reports and the units' noise estimates, stored, migrated from v4 and
// read back through the views and queries `gyrocal show` uses.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "store/db/fit_query.hpp"
#include "store/db/query.hpp"
#include "store/db/schema.hpp"
#include "store/db/writer.hpp"
#include "tests/store/scratch_db.hpp"

namespace gyrocal::db {
namespace {

using testing::Count;
using testing::FreshDbPath;
using testing::OldDatabase;

// A row about the fitter's set `set_id` of unit U1 in run R1 (the set itself, or its report).
template <class R>
R OfFitterSet(int64_t set_id) {
    R r;
    r.run_id = "R1";
    r.sensor_id = "U1";
    r.source = "fitter";
    r.coeff_set_id = set_id;
    r.utime = set_id;
    return r;
}

FitReportRow Report(int64_t set_id, bool final, const std::string& status) {
    FitReportRow r = OfFitterSet<FitReportRow>(set_id);
    r.is_final = final;
    r.status = status;
    r.reason = status == "complete" ? "" : "sensitivity: nominal";
    r.slow_noise_v = 8e-5;
    r.slow_noise_dps = 8e-5 / 0.006;
    r.slow_noise_source = "Allan deviation of this run";
    r.excluded.push_back(
        {"plateau", 3000, 30.2, 2.51, 3e-3, 1e-4, 30.0, 4.1, "leave-one-out: ..."});
    r.repeats.push_back({25.1, 1000, 7000, 25.0, 25.2, 0, -1, 1e-4, 4e-5, 0.0167, 0.0067, 2.5,
                         "repeatable within 3 sigma"});
    r.recv_utime = 50;
    return r;
}

NoiseRow Noise(int64_t utime, double bias_v) {
    NoiseRow n;
    n.run_id = "R1";
    n.sensor_id = "U1";
    n.utime = utime;
    n.still_s = 1800;
    n.n_segments = 6;
    n.arw_v_rthz = 2.4e-4;
    n.bias_instability_v = bias_v;
    n.bias_instability_stderr_v = 6e-6;
    n.rrw_v_rts = 0.0;
    n.tau_s = {0.1, 1.0, 10.0};
    n.adev_v = {7.6e-4, 2.4e-4, 8e-5};
    n.adev_lo_v = {7.5e-4, 2.3e-4, 7e-5};
    n.adev_hi_v = {7.7e-4, 2.5e-4, 9e-5};
    n.edf = {10000, 1000, 30};
    n.recv_utime = utime;
    return n;
}

CoeffSetRow Set(int64_t id, double sensitivity) {
    CoeffSetRow c = OfFitterSet<CoeffSetRow>(id);
    c.recv_utime = 60;
    for (ModelRow* m : {&c.offset, &c.sensitivity}) {
        m->term_names = {"1"};
        m->coeffs = {m == &c.offset ? 2.5 : sensitivity};
        m->covariance = {{1e-10}};
        m->method = "mean";
    }
    c.offset.quantity = "offset_v";
    c.sensitivity.quantity = "sensitivity_v_per_dps";
    return c;
}

TEST(FitReports, FinalReportExclusionsRepeatabilityAndNoiseReadBack) {
    const std::string path = FreshDbPath("fit.db");
    StoreWriter w(path, {"test", "h", 1});
    // a mid-run report, then the final one; two noise estimates; the run's final set
    w.Write({Report(100, false, "partial"), Report(200, true, "complete"), Noise(10, 4e-5),
             Noise(20, 5e-5), Set(200, 0.0058)},
            {});
    Db& db = w.db();
    EXPECT_EQ(Count(db, "SELECT count(*) FROM fit_reports"), 2);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM fit_exclusions"), 2);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM noise_adev"), 6);
    // the final report wins, with its exclusion and repeatability
    const std::vector<FitReportInfo> reports = RunFitReports(db, "R1");
    ASSERT_EQ(reports.size(), 1u);
    EXPECT_TRUE(reports[0].report.is_final);
    EXPECT_EQ(reports[0].report.coeff_set_id, 200);
    ASSERT_EQ(reports[0].report.excluded.size(), 1u);
    EXPECT_EQ(reports[0].report.excluded[0].item_id, 3000);
    ASSERT_EQ(reports[0].report.repeats.size(), 1u);
    EXPECT_EQ(reports[0].report.repeats[0].second_approach, -1);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM v_repeatability"), 1);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM v_fit_final WHERE excluded = 'plateau 3000'"), 1);
    // the newest noise, in deg/s through the final set's sensitivity
    const std::vector<NoiseInfo> noise = RunNoise(db, "R1");
    ASSERT_EQ(noise.size(), 1u);
    EXPECT_EQ(noise[0].noise.utime, 20);
    ASSERT_TRUE(noise[0].sensitivity_v_per_dps);
    EXPECT_DOUBLE_EQ(*noise[0].sensitivity_v_per_dps, 0.0058);
    EXPECT_EQ(noise[0].noise.tau_s.size(), 3u);
    Stmt dps(db, "SELECT bias_instability_dps FROM v_noise WHERE sensor_id = 'U1'");
    ASSERT_TRUE(dps.Step());
    EXPECT_DOUBLE_EQ(dps.Real(0), 5e-5 / 0.0058);
    // and ShowRun carries both
    const RunDetail d = ShowRun(db, "R1");
    EXPECT_EQ(d.fit_reports.size(), 1u);
    EXPECT_EQ(d.noise.size(), 1u);
}

TEST(FitReports, AVersionFourFileGainsTheTablesAndKeepsItsRows) {
    const std::string path = FreshDbPath("v4.db");
    {
        OldDatabase db(path, 4);
        db.Exec("INSERT INTO runs(run_id, outcome, first_recv_utime) VALUES ('OLD', 'stop', 1)");
    }
    StoreWriter w(path, {"test", "h", 1});
    EXPECT_EQ(w.db().UserVersion(), kSchemaVersion);
    EXPECT_EQ(Count(w.db(), "SELECT count(*) FROM runs WHERE run_id = 'OLD'"), 1);
    EXPECT_EQ(Count(w.db(),
                    "SELECT count(*) FROM sqlite_master WHERE name IN ('fit_reports', "
                    "'fit_exclusions', 'repeatability', 'noise_estimates', 'noise_adev', "
                    "'v_fit_final', 'v_repeatability', 'v_noise')"),
              8);
    EXPECT_TRUE(RunFitReports(w.db(), "OLD").empty());
}

}  // namespace
}  // namespace gyrocal::db
