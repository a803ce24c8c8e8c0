// Schema v4 and the analyses API without LCM: migration from every earlier version, analyses
// stored with their run and their extended coefficient set in one transaction, and a
// coefficient set kept once per (run, sensor, coeff_set_id, source) whoever writes it first.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "store/db/analyses.hpp"
#include "store/db/query.hpp"
#include "store/db/schema.hpp"
#include "store/db/validations.hpp"
#include "store/db/writer.hpp"
#include "tests/store/row_builders.hpp"
#include "tests/store/scratch_db.hpp"

namespace gyrocal::db {
namespace {

using testing::Count;
using testing::FreshDbPath;
using testing::OldDatabase;

RunEventRow Start(const std::string& run) { return testing::RunEvent(run, "start", {"S01"}, 100); }

CoeffSetRow Set(const std::string& run, int64_t id, const std::string& source, int64_t recv) {
    CoeffSetRow c;
    c.run_id = run;
    c.sensor_id = "S01";
    c.coeff_set_id = id;
    c.utime = id;
    c.source = source;
    for (ModelRow* m : {&c.offset, &c.sensitivity}) {
        m->term_names = {"1", "dT"};
        m->coeffs = {2.5, 1e-3};
        m->covariance = {{1e-8, 0}, {0, 1e-8}};
        m->t0_c = 25;
        m->temp_min_c = 0;
        m->temp_max_c = 50;
    }
    c.offset.quantity = "offset_v";
    c.sensitivity.quantity = "sensitivity_v_per_dps";
    c.recv_utime = recv;
    return c;
}

AnalysisRow Analysis(const std::string& run) {
    AnalysisRow a;
    a.run_id = run;
    a.sensor_id = "S01";
    a.created_wall_utime = 5000;
    a.software_version = "v9";
    a.command_line = "gyrocal analyze R1 --publish";
    a.verdict = "added temp_rate";
    a.candidates_json = R"([{"effect":"temp_rate","statistic":41.5,"decision":"added"}])";
    a.added_json =
        R"j([{"effect":"temp_rate","term":"dTdt","coefficient":0.01,"stderr":0.001,"unit":"V/(degC/s)"}])j";
    testing::SetErrors(a, {2e-4, 5e-5}, {0.03, 0.008}, {90, 20});
    // floor_rate_rms_dps left NaN: stored as NULL, read back as NaN
    a.result_json = R"({"sensor_id":"S01","verdict":"added temp_rate"})";
    return a;
}

// GIVEN a database at each earlier schema version with a run and two rows of one coefficient
// set key (possible before v4), WHEN the writer opens it, THEN it is at the current version,
// nothing was lost, and the v4 behaviour holds on the migrated file.
class MigrateFrom : public ::testing::TestWithParam<int> {};

TEST_P(MigrateFrom, EveryEarlierVersionToTheCurrentOne) {
    const int from = GetParam();
    const std::string path = FreshDbPath("from_v" + std::to_string(from) + ".db");
    {
        OldDatabase db(path, from);
        ASSERT_EQ(db.UserVersion(), from);
        EXPECT_EQ(Count(db, "SELECT count(*) FROM sqlite_master WHERE name = 'analyses'"),
                  from >= 4 ? 1 : 0);
        EXPECT_EQ(Count(db, "SELECT count(*) FROM sqlite_master WHERE name = 'validations'"),
                  from >= 5 ? 1 : 0);
        db.Exec(
            "INSERT INTO runs(run_id, started_utime, outcome, first_recv_utime) "
            "VALUES ('OLD', 1, 'running', 10)");
        db.Exec(
            "INSERT INTO rates(run_id, sensor_id, utime, rate_dps, recv_utime) "
            "VALUES ('OLD', 'S01', 5, 0.1, 11)");
        for (int k = 0; k < 2; ++k) {
            db.Exec(
                "INSERT INTO coeff_sets(run_id, sensor_id, coeff_set_id, source, utime, "
                "recv_utime) VALUES ('OLD', 'S01', 7, 'fitter', 7, 12)");
        }
    }
    StoreWriter w(path, {"test", "h", 1});
    Db& db = w.db();
    EXPECT_EQ(db.UserVersion(), kSchemaVersion);
    EXPECT_EQ(kSchemaVersion, 9);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_sets"), 2);  // history is never rewritten
    EXPECT_EQ(Count(db, "SELECT count(*) FROM rates"), 1);
    EXPECT_EQ(Count(db,
                    "SELECT count(*) FROM sqlite_master WHERE type = 'index' AND name IN "
                    "('coeff_sets_key', 'analyses_run')"),
              2);
    // The writer's existence check is an index seek, not a scan of every set ever stored.
    {
        Stmt plan(db,
                  "EXPLAIN QUERY PLAN SELECT coeff_row_id FROM coeff_sets WHERE run_id = 'a' "
                  "AND sensor_id = 'b' AND coeff_set_id = 1 AND source = 'c'");
        std::string text;
        while (plan.Step()) text += plan.Text(3) + "\n";
        EXPECT_NE(text.find("coeff_sets_key"), std::string::npos) << text;
    }
    // An existing key is not stored again; an analysis and its set go in.
    w.Write({Set("OLD", 7, "fitter", 20)}, {});
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_sets"), 2);
    const CoeffSetRow ext = Set("OLD", 7, "ignored", 0);
    const StoredAnalysis a = StoreAnalysis(db, Analysis("OLD"), &ext);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM v_analyses WHERE source = 'analysis:" +
                            std::to_string(a.analysis_id) + "'"),
              1);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM pragma_integrity_check WHERE integrity_check = 'ok'"),
              1);
}

// GIVEN a v6 database with a plateau (its temperature-line mean under the old name temp_v_mean),
// WHEN the writer opens it, THEN the value is read back under the fixed name temp_mean_v.
TEST(MigrateRename, PlateauTempLineMeanKeepsItsValueUnderTheFixedName) {
    const std::string path = FreshDbPath("rename_v6.db");
    OldDatabase(path, 6).Exec(
        "INSERT INTO plateaus(run_id, sensor_id, plateau_id, utime, temp_v_mean, recv_utime) "
        "VALUES ('OLD', 'S01', 1, 5, 2.545, 6)");
    StoreWriter w(path, {"test", "h", 1});
    Stmt s(w.db(), "SELECT temp_mean_v FROM plateaus WHERE run_id = 'OLD'");
    ASSERT_TRUE(s.Step());
    EXPECT_EQ(s.Real(0), 2.545);  // a rename copies nothing: the stored double itself
    EXPECT_EQ(Count(w.db(),
                    "SELECT count(*) FROM pragma_table_info('plateaus') "
                    "WHERE name = 'temp_v_mean'"),
              0);
}

INSTANTIATE_TEST_SUITE_P(Schema, MigrateFrom, ::testing::Range(1, kSchemaVersion),
                         [](const auto& info) { return "V" + std::to_string(info.param); });

// GIVEN a v6 database with analyses whose result_json carries an outcome, none, a non-text
// outcome or is not JSON at all, WHEN it is migrated to v8, THEN analyses.outcome holds the
// outcome where one was stored and NULL elsewhere (never a guess), v_analyses shows it, and a
// new analysis stores its outcome and reads it back.
TEST(Analyses, V8BackfillsTheOutcomeFromResultJsonWherePresent) {
    const std::string path = FreshDbPath("outcome_v8.db");
    {
        OldDatabase db(path, 6);
        db.Exec(
            "INSERT INTO runs(run_id, started_utime, outcome, first_recv_utime) "
            "VALUES ('R6', 1, 'done', 10)");
        const char* results[] = {R"({"outcome":"explained","verdict":"missing effect: supply"})",
                                 R"({"verdict":"no missing effect"})", R"({"outcome":3})",
                                 "not json", R"({"outcome":"something newer"})"};
        for (const char* r : results) {
            Stmt s(db,
                   "INSERT INTO analyses(run_id, sensor_id, created_wall_utime, result_json) "
                   "VALUES ('R6', 'S01', 1, ?)");
            s.Bind(1, r).Run();
        }
    }
    Db db(path, Db::Mode::kReadWrite);
    Migrate(db);
    EXPECT_EQ(db.UserVersion(), kSchemaVersion);
    const std::vector<AnalysisRow> rows = ListAnalyses(db, "R6");
    ASSERT_EQ(rows.size(), 5u);
    EXPECT_EQ(rows[0].outcome, std::optional<std::string>("explained"));
    EXPECT_FALSE(rows[1].outcome.has_value());
    EXPECT_FALSE(rows[2].outcome.has_value());
    EXPECT_FALSE(rows[3].outcome.has_value());
    // An outcome this version does not know is kept as written: the reader judges it (acceptance
    // says "not evaluated" and names it), the migration does not rewrite history.
    EXPECT_EQ(rows[4].outcome, std::optional<std::string>("something newer"));
    EXPECT_EQ(Count(db, "SELECT count(*) FROM v_analyses WHERE outcome = 'explained'"), 1);
    AnalysisRow a = Analysis("R6");
    a.outcome = "partly explained";
    StoreAnalysis(db, a);
    EXPECT_EQ(ListAnalyses(db, "R6").back().outcome,
              std::optional<std::string>("partly explained"));
}

TEST(Analyses, StoredWithTheirRunAndExtendedSetInOneGo) {
    const std::string path = FreshDbPath("analyses.db");
    StoreWriter w(path, {"test", "h", 1});
    w.Write({Start("R1"), Set("R1", 77, "fitter", 200)}, {});
    Db& db = w.db();

    // WHEN an analysis with an extended set is stored
    CoeffSetRow ext = Set("SOMETHING ELSE", 77, "ignored", 0);
    ext.offset.term_names = {"1", "dT", "dTdt"};
    ext.offset.coeffs = {2.5, 1e-3, 0.01};
    ext.offset.covariance.assign(3, std::vector<double>(3, 0.0));
    const StoredAnalysis a = StoreAnalysis(db, Analysis("R1"), &ext);

    // THEN the set carries the analysis as its source, the run analysed and the creation time
    ASSERT_TRUE(a.coeff_row_id);
    EXPECT_EQ(a.source, "analysis:" + std::to_string(a.analysis_id));
    EXPECT_EQ(a.source, AnalysisSource(a.analysis_id));
    Stmt s(db, "SELECT run_id, source, recv_utime FROM coeff_sets WHERE coeff_row_id = ?");
    s.Bind(1, *a.coeff_row_id);
    ASSERT_TRUE(s.Step());
    EXPECT_EQ(s.Text(0), "R1");
    EXPECT_EQ(s.Text(1), a.source);
    EXPECT_EQ(s.Int(2), 5000);
    EXPECT_EQ(Count(db,
                    "SELECT count(*) FROM coeff_terms WHERE role = 'offset' AND "
                    "coeff_row_id = " +
                        std::to_string(*a.coeff_row_id)),
              3);
    // ... and reads back whole, NaN as NaN, the link set
    const auto list = ListAnalyses(db, "R1");
    ASSERT_EQ(list.size(), 1u);
    const AnalysisRow& r = list[0];
    EXPECT_EQ(r.analysis_id, a.analysis_id);
    EXPECT_EQ(r.coeff_row_id, a.coeff_row_id);
    EXPECT_EQ(r.verdict, "added temp_rate");
    EXPECT_EQ(r.added_json, Analysis("R1").added_json);
    EXPECT_EQ(r.rate_rms_dps_after, 0.008);
    EXPECT_TRUE(std::isnan(r.floor_rate_rms_dps));
    EXPECT_EQ(r.command_line, "gyrocal analyze R1 --publish");
    // The view: the effects added, side by side with the before/after figures.
    Stmt v(db, "SELECT added_effects, rate_rms_dps_before, source FROM v_analyses");
    ASSERT_TRUE(v.Step());
    EXPECT_EQ(v.Text(0), "temp_rate");
    EXPECT_EQ(v.Real(1), 0.03);
    EXPECT_EQ(v.Text(2), a.source);
    // The run's detail lists it; the export of the run takes the newest set (the analysis').
    const RunDetail d = ShowRun(db, "R1");
    EXPECT_EQ(d.analyses.size(), 1u);
    EXPECT_EQ(d.coeff_sets.size(), 2u);  // final of each source
    const auto newest = RunNewestCoeffs(db, "R1");
    ASSERT_EQ(newest.size(), 1u);
    EXPECT_EQ(newest[0].set.source, a.source);

    // An analysis without a model, and one of another sensor's listing.
    const StoredAnalysis b = StoreAnalysis(db, Analysis("R1"));
    EXPECT_FALSE(b.coeff_row_id);
    EXPECT_GT(b.analysis_id, a.analysis_id);
    EXPECT_EQ(ListAnalyses(db, "R1").size(), 2u);
    EXPECT_EQ(ListAnalyses(db, "R1", std::string("S02")).size(), 0u);
}

TEST(Analyses, TheFittersClosedLoopIsStoredAsAnAnalysisLinkedToTheSetItMade) {
    // GIVEN the fitter's closed-loop final set and its ANALYSIS_ message, recorded in one batch
    const std::string path = FreshDbPath("closed_loop.db");
    StoreWriter w(path, {"recorder-v1", "h", 1});
    ClosedLoopRow a;
    a.run_id = "R1", a.sensor_id = "S01", a.source = "closed-loop", a.utime = 88,
    a.coeff_set_id = 88;
    a.is_final = true, a.outcome = "explained", a.headline = "missing effect: supply, explained";
    a.candidates_json = "[]", a.added_json = R"([{"effect":"supply"}])", a.result_json = "{}";
    a.offset_rms_v_before = 1e-3, a.offset_rms_v_after = 2e-4, a.rate_rms_dps_before = 0.2;
    a.rate_rms_dps_after = 0.03, a.drift_dph_before = 90, a.drift_dph_after = 20;
    a.floor_rate_rms_dps = 0.01, a.recv_utime = 7000;
    w.Write({Start("R1"), Set("R1", 88, "fitter", 300), Set("R1", 88, "closed-loop", 301), a}, {});
    // THEN it is an analysis of the run, its verdict the headline, linked to the closed loop's set
    // (not the plateau set of the same id), with the recorder's version
    const auto rows = ListAnalyses(w.db(), "R1");
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].verdict, a.headline);
    EXPECT_EQ(*rows[0].outcome, "explained");
    EXPECT_EQ(rows[0].software_version, "recorder-v1");
    EXPECT_DOUBLE_EQ(rows[0].rate_rms_dps_after, 0.03);
    ASSERT_TRUE(rows[0].coeff_row_id.has_value());
    EXPECT_EQ(
        Count(w.db(),
              "SELECT count(*) FROM coeff_sets WHERE source = 'closed-loop' AND coeff_row_id = " +
                  std::to_string(*rows[0].coeff_row_id)),
        1);
    // AND an analysis that made no set links none
    a.coeff_set_id = -1;
    w.Write({a}, {});
    EXPECT_FALSE(ListAnalyses(w.db(), "R1").back().coeff_row_id.has_value());
}

TEST(Analyses, RefusalsWriteNothing) {
    const std::string path = FreshDbPath("analyses_bad.db");
    StoreWriter w(path, {"test", "h", 1});
    w.Write({Start("R1")}, {});
    Db& db = w.db();
    const CoeffSetRow ext = Set("R1", 1, "x", 0);
    EXPECT_THROW(StoreAnalysis(db, Analysis("NOPE"), &ext), NotFound);
    CoeffSetRow other = ext;
    other.sensor_id = "S02";
    EXPECT_THROW(StoreAnalysis(db, Analysis("R1"), &other), StoreError);
    AnalysisRow no_sensor = Analysis("R1");
    no_sensor.sensor_id.clear();
    EXPECT_THROW(InsertAnalysis(db, no_sensor), StoreError);
    EXPECT_THROW(ListAnalyses(db, "NOPE"), NotFound);
    CoeffSetRow no_source = ext;
    no_source.source.clear();
    EXPECT_THROW(StoreCoeffSet(db, no_source), StoreError);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM analyses"), 0);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_sets"), 0);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM runs WHERE run_id = 'NOPE'"), 0);
    EXPECT_THROW(OpenForUpdate(FreshDbPath("missing.db")), StoreError);
}

// A validation's command line is stored as an analysis' is: a password in a database URL on it
// (gyrocal validate --db postgresql://user:pw@host/db) never reaches the database.
TEST(Validations, TheCommandLineIsStoredWithoutItsPassword) {
    const std::string path = FreshDbPath("validations_pw.db");
    StoreWriter w(path, {"test", "h", 1});
    w.Write({Start("R1")}, {});
    ValidationRow v;
    v.run_id = "R1";
    v.sensor_id = "S01";
    v.command_line = "gyrocal validate --db postgresql://lab:s3cret@central/gyrocal R1";
    v.model_origin = "newest set";
    InsertValidation(w.db(), v);
    const std::vector<ValidationRow> stored = ListValidations(w.db(), "R1");
    ASSERT_EQ(stored.size(), 1u);
    EXPECT_EQ(stored[0].command_line.find("s3cret"), std::string::npos) << stored[0].command_line;
    EXPECT_NE(stored[0].command_line.find("postgresql://lab:***@central/gyrocal"),
              std::string::npos)
        << stored[0].command_line;
}

TEST(CoeffSets, KeptOncePerKeyWhoeverWritesFirst) {
    const std::string path = FreshDbPath("coeff_once.db");
    StoreWriter w(path, {"test", "h", 1});
    w.Write({Start("R1")}, {});
    // GIVEN a set stored directly through a second connection (as gyrocal analyze does)
    auto other = OpenForUpdate(path);
    const int64_t direct = StoreCoeffSet(*other, Set("R1", 5, "analysis:1", 300));
    EXPECT_EQ(StoreCoeffSet(*other, Set("R1", 5, "analysis:1", 301)), direct);  // again: same row
    // WHEN the recorder hears it, twice, and the fitter's set of the same id in another batch
    w.Write({Set("R1", 5, "analysis:1", 400), Set("R1", 5, "analysis:1", 401),
             Set("R1", 5, "fitter", 402)},
            {});
    w.Write({Set("R1", 5, "fitter", 403), Set("R1", 6, "fitter", 404)}, {});
    // THEN one row per (run, sensor, coeff_set_id, source), the first one written
    Db& db = w.db();
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_sets"), 3);
    EXPECT_EQ(Count(db, "SELECT recv_utime FROM coeff_sets WHERE coeff_row_id = " +
                            std::to_string(direct)),
              300);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_terms"), 3 * 4);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_covariance"), 3 * 8);
    // Another run with the same id and source is another set.
    w.Write({Start("R2"), Set("R2", 5, "fitter", 500)}, {});
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_sets"), 4);
}

}  // namespace
}  // namespace gyrocal::db
