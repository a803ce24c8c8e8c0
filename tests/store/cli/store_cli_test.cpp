// The store commands as a user runs them (through a driver identical to gyrocal's main), on a
// fixture database with known contents: output, exit codes, bad ids and hostile strings.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fixture.hpp"
#include "launch/child_process.hpp"
#include "sqlite_db.hpp"

namespace gyrocal::testing {
namespace {

using namespace std::chrono_literals;

struct Result {
    int code = -1;
    std::string out, err;
};

std::string Slurp(const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

class StoreCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = (std::filesystem::temp_directory_path() /
                ("gyrocal_store_cli_" + std::to_string(::getpid()))).string();
        std::filesystem::create_directories(dir_);
        db_ = dir_ + "/fixture.db";
        std::filesystem::remove(db_);
        WriteFixture(db_);
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

    static Result Run(std::vector<std::string> args) {
        args.insert(args.begin(), std::string(GYROCAL_BIN_DIR) + "/store_cli_driver");
        const std::string out = dir_ + "/out.txt", err = dir_ + "/err.txt";
        ChildProcess p(args, out, err);
        const auto st = p.Wait(30s);
        Result r;
        r.code = st && st->exited ? st->code : -1;
        r.out = Slurp(out);
        r.err = Slurp(err);
        return r;
    }
    static Result RunDb(std::vector<std::string> args) {
        args.push_back("--db");
        args.push_back(db_);
        return Run(args);
    }
    static int64_t RunsInDb() {
        store::Db db(db_, store::Db::Mode::kReadOnly);
        store::Stmt s(db, "SELECT count(*) FROM runs");
        s.Step();
        return s.Int(0);
    }

    static std::string dir_, db_;
};
std::string StoreCli::dir_, StoreCli::db_;

int Lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST_F(StoreCli, RunsListsNewestFirstWithCountsAndLosses) {
    const Result r = RunDb({"runs", "--json"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j.size(), 4u);  // R3, R2, R1, then the no-run bucket
    EXPECT_EQ(j[0]["run_id"], "R3");
    EXPECT_EQ(j[1]["run_id"], "R2");
    EXPECT_EQ(j[2]["run_id"], "R1");
    EXPECT_EQ(j[3]["run_id"], "");
    EXPECT_EQ(j[2]["counts"]["gyro_samples"], 600);
    EXPECT_EQ(j[2]["losses"]["seq_gaps"], 3);
    EXPECT_EQ(j[2]["losses"]["queue_drops"], 2);
    EXPECT_EQ(j[1]["outcome"], "abort");
    EXPECT_EQ(j[3]["counts"]["gyro_samples"], 5);

    const Result t = RunDb({"runs"});
    ASSERT_EQ(t.code, 0);
    EXPECT_EQ(Lines(t.out), 2 + 4);  // header, rule, 4 runs
    EXPECT_LT(t.out.find("R3"), t.out.find("R1"));
    EXPECT_NE(t.out.find("(no run)"), std::string::npos);
}

TEST_F(StoreCli, RunsFilters) {
    auto ids = [](const Result& r) {
        std::vector<std::string> v;
        for (const auto& e : nlohmann::json::parse(r.out)) v.push_back(e["run_id"]);
        return v;
    };
    EXPECT_EQ(ids(RunDb({"runs", "--json", "--outcome", "abort"})), std::vector<std::string>{"R2"});
    EXPECT_EQ(ids(RunDb({"runs", "--json", "--sensor", "S02"})), std::vector<std::string>{"R1"});
    EXPECT_EQ(ids(RunDb({"runs", "--json", "--sensor", "S01"})),
              (std::vector<std::string>{"R2", "R1"}));
    EXPECT_EQ(ids(RunDb({"runs", "--json", "--since", "2026-01-15", "--until", "2026-01-25"})),
              std::vector<std::string>{"R2"});
    EXPECT_EQ(ids(RunDb({"runs", "--json", "--since", "2026-01-21T00:00:00Z", "--outcome",
                         "running"})), std::vector<std::string>{"R3"});
    const Result none = RunDb({"runs", "--since", "2030-01-01"});
    EXPECT_EQ(none.code, 0);
    EXPECT_NE(none.out.find("no runs match"), std::string::npos);
    EXPECT_EQ(ids(RunDb({"runs", "--json", "--sensor", "' OR 1=1 --"})), std::vector<std::string>{});
}

TEST_F(StoreCli, BadOptionValuesExitTwo) {
    EXPECT_EQ(RunDb({"runs", "--since", "last tuesday"}).code, 2);
    EXPECT_EQ(RunDb({"runs", "--since", "2026-02-31"}).code, 2);
    EXPECT_EQ(RunDb({"runs", "--outcome", "exploded"}).code, 2);
    EXPECT_EQ(RunDb({"history", "S01", "--ref-temps-c", "0,abc"}).code, 2);
    EXPECT_EQ(RunDb({"export", "R1", "--format", "xml"}).code, 2);
    EXPECT_EQ(RunDb({"replay", "R1", "--max", "--speed", "2"}).code, 2);
    EXPECT_EQ(Run({"frobnicate"}).code, 2);
    EXPECT_EQ(Run({"show"}).code, 2);  // run id required
}

TEST_F(StoreCli, ShowRunHasEverythingAndProvenance) {
    const Result r = RunDb({"show", "R1", "--json"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["software_version"], "v1.2.3");
    EXPECT_EQ(j["config"]["setpoints_c"][2], 50);
    EXPECT_EQ(j["plateaus"].size(), 1u);
    EXPECT_EQ(j["sensitivity_points"].size(), 1u);
    ASSERT_EQ(j["coeff_sets"].size(), 3u);  // final set of S01, S02 and the hostile id
    nlohmann::json s01;
    for (const auto& set : j["coeff_sets"]) {
        if (set["sensor_id"] == "S01") s01 = set;
    }
    ASSERT_EQ(s01["sensor_id"], "S01");
    EXPECT_EQ(s01["coeff_set_id"], 11);  // not the superseded 10
    ASSERT_EQ(s01["provenance"].size(), 2u);
    for (const auto& item : s01["provenance"]) {
        EXPECT_TRUE(item["found"].get<bool>());
        EXPECT_EQ(item["stored_gyro_samples"], 100);  // seq 0..99 and 100..199
    }
    EXPECT_EQ(j["loss_by_channel"].size(), 2u);
    EXPECT_EQ(j["events"].size(), 2u);
    ASSERT_EQ(j["processes"].size(), 1u);
    EXPECT_EQ(j["processes"][0]["received"], 200);  // the newest heartbeat
    EXPECT_EQ(j["processes"][0]["seq_gaps"], 7);

    const Result t = RunDb({"show", "R1"});
    ASSERT_EQ(t.code, 0);
    for (const char* s : {"v1.2.3", "Plateaus (1)", "Sensitivity points (1)", "offset_v",
                          "GYRO_S01", "(recorder)", "200 raw gyro samples stored",
                          "gyrocal-plateau", "non_finite: temp_c is NaN"}) {
        EXPECT_NE(t.out.find(s), std::string::npos) << s << " missing in:\n" << t.out;
    }
}

TEST_F(StoreCli, UnknownAndHostileIdsAreAClearErrorAndChangeNothing) {
    const int64_t runs_before = RunsInDb();
    for (const std::string id : {"NOPE", "R1' OR '1'='1", "'; DROP TABLE runs; --", "R1\"",
                                 "%", "R_"}) {
        for (const std::vector<std::string>& cmd :
             {std::vector<std::string>{"show", id}, {"export", id, "--kind", "run"},
              {"history", id}, {"export", id}}) {
            const Result r = RunDb(cmd);
            EXPECT_EQ(r.code, 1) << cmd[0] << " " << id;
            EXPECT_EQ(r.out, "");
            EXPECT_EQ(Lines(r.err), 1) << r.err;
            EXPECT_NE(r.err.find("gyrocal " + cmd[0] + ": error:"), std::string::npos) << r.err;
        }
    }
    EXPECT_EQ(RunsInDb(), runs_before);
    // Replay refuses an unknown run the same way (through gyrocal-replay).
    const Result rp = RunDb({"replay", "'; DROP TABLE runs; --", "--max"});
    EXPECT_EQ(rp.code, 1);
    EXPECT_NE(rp.err.find("no run"), std::string::npos) << rp.err;
}

TEST_F(StoreCli, MissingOrForeignDatabaseIsOneLineAndExitOne) {
    const Result r = Run({"runs", "--db", dir_ + "/does-not-exist.db"});
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(Lines(r.err), 1);
    EXPECT_NE(r.err.find("does not exist"), std::string::npos);
    const std::string junk = dir_ + "/junk.db";
    std::ofstream(junk) << "this is not sqlite, it is a text file long enough to have a header";
    const Result j = Run({"show", "R1", "--db", junk});
    EXPECT_EQ(j.code, 1);
    EXPECT_EQ(Lines(j.err), 1) << j.err;
}

TEST_F(StoreCli, HistoryShowsHowCoefficientsMoved) {
    const Result r = RunDb({"history", "S01", "--json", "--ref-temps-c", "0,25,50"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const auto& sets = j["coeff_sets"];
    ASSERT_EQ(sets.size(), 2u);  // final of R1, final of R2
    EXPECT_EQ(sets[0]["coeff_set_id"], 11);
    EXPECT_EQ(sets[1]["coeff_set_id"], 21);
    for (size_t k = 0; k < 3; ++k) {
        const double t = sets[0]["at_ref_temps"][k]["temp_c"];
        const double dT = t - 25.0;
        // Known truth of the fixture: offset 2.5 + 1e-3 dT - 2e-5 dT^2, moved by +1 mV.
        const double off0 = sets[0]["at_ref_temps"][k]["offset_v"];
        const double off1 = sets[1]["at_ref_temps"][k]["offset_v"];
        EXPECT_NEAR(off0, 2.5 + 1e-3 * dT - 2e-5 * dT * dT, 1e-12);
        EXPECT_NEAR(off1 - off0, 1e-3, 1e-12);
        const double s0 = sets[0]["at_ref_temps"][k]["sensitivity_v_per_dps"];
        const double s1 = sets[1]["at_ref_temps"][k]["sensitivity_v_per_dps"];
        EXPECT_NEAR(s0, 0.0067 + 1e-6 * dT, 1e-15);
        EXPECT_NEAR(s1 - s0, 0.0067 * 0.01, 1e-15);
    }
    const Result all = RunDb({"history", "S01", "--all", "--json"});
    EXPECT_EQ(nlohmann::json::parse(all.out)["coeff_sets"].size(), 3u);
    const Result t = RunDb({"history", "S01"});
    ASSERT_EQ(t.code, 0);
    EXPECT_EQ(Lines(t.out), 1 + 2 + 2 * 3 + 1);  // title, header+rule, 2 sets x 3 temps, note
    EXPECT_NE(t.out.find("D_OFFSET_MV"), std::string::npos);
}

TEST_F(StoreCli, ExportJsonAndCsv) {
    const Result j = RunDb({"export", "R1", "--format", "json"});
    ASSERT_EQ(j.code, 0) << j.err;
    const auto doc = nlohmann::json::parse(j.out);
    EXPECT_EQ(doc["coeff_sets"].size(), 3u);
    const Result s = RunDb({"export", "S01", "--format", "json"});
    ASSERT_EQ(s.code, 0) << s.err;
    const auto sdoc = nlohmann::json::parse(s.out);
    ASSERT_EQ(sdoc["coeff_sets"].size(), 1u);
    EXPECT_EQ(sdoc["coeff_sets"][0]["coeff_set_id"], 21);  // the newest
    EXPECT_EQ(sdoc["coeff_sets"][0]["offset"]["term_names"][2], "dT^2");

    const std::string csv_path = dir_ + "/r1.csv";
    const Result c = RunDb({"export", "R1", "--format", "csv", "--out", csv_path});
    ASSERT_EQ(c.code, 0) << c.err;
    EXPECT_EQ(c.out, "");
    const std::string csv = Slurp(csv_path);
    EXPECT_EQ(Lines(csv), 1 + 3 * (3 + 2));  // header + 3 sets x (3 offset + 2 sens terms)
    EXPECT_NE(csv.find("\"X\"\"*/ '; DROP TABLE runs; --\""), std::string::npos);  // quoted
    EXPECT_EQ(RunDb({"export", "R3"}).code, 1);  // a run without coefficient sets
    const Result w = RunDb({"export", "R1", "--out", "/nonexistent-dir/x.json"});
    EXPECT_EQ(w.code, 1);
    EXPECT_EQ(Lines(w.err), 1);
}

// The C header compiles (even with a hostile sensor id) and evaluates the models as stored.
TEST_F(StoreCli, CHeaderCompilesAndEvaluates) {
    const std::string h = dir_ + "/coeffs.h";
    ASSERT_EQ(RunDb({"export", "R1", "--format", "c-header", "--out", h}).code, 0);
    const std::string c = dir_ + "/use.c", exe = dir_ + "/use";
    std::ofstream(c) << "#include <stdio.h>\n#include \"coeffs.h\"\n"
                        "int main(void) {\n"
                        "  printf(\"%.12f %.12f %.12f %lld\\n\", gyrocal_eval(&gyrocal_S01_offset, 35.0),\n"
                        "         gyrocal_eval(&gyrocal_S01_sensitivity, 35.0),\n"
                        "         gyrocal_eval(&gyrocal_S01_offset, 100.0),\n"
                        "         (long long)GYROCAL_S01_COEFF_SET_ID);\n"
                        "  return 0;\n}\n";
    ChildProcess cc({"cc", "-std=c99", "-Wall", "-Wextra", "-Werror", "-Wno-unused-const-variable",
                     "-o", exe, c, "-lm"}, "", dir_ + "/cc.err");
    const auto st = cc.Wait(60s);
    ASSERT_TRUE(st && st->exited && st->code == 0) << Slurp(dir_ + "/cc.err");
    ChildProcess run({exe}, dir_ + "/use.out", "");
    ASSERT_TRUE(run.Wait(10s));
    double off = 0, sens = 0, off_clip = 0;
    long long id = 0;
    std::istringstream(Slurp(dir_ + "/use.out")) >> off >> sens >> off_clip >> id;
    const double dT = 10.0, dT_max = 35.0;  // 35 C, and 100 C clipped to temp_max_c = 60 C
    EXPECT_NEAR(off, 2.5 + 1e-3 * dT - 2e-5 * dT * dT, 1e-12);
    EXPECT_NEAR(sens, 0.0067 + 1e-6 * dT, 1e-15);
    EXPECT_NEAR(off_clip, 2.5 + 1e-3 * dT_max - 2e-5 * dT_max * dT_max, 1e-12);
    EXPECT_EQ(id, 11);
}

}  // namespace
}  // namespace gyrocal::testing
