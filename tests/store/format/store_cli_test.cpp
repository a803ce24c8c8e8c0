// The store commands as a user runs them (through a driver identical to gyrocal's main), on a
// fixture database with known contents: output, exit codes, bad ids and hostile strings.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "lcmtypes/launch/child_process.hpp"
#include "processors/model/c_source.hpp"
#include "processors/model/json.hpp"
#include "processors/model/model.hpp"
#include "store/db/model_rows.hpp"
#include "store/db/sqlite_db.hpp"
#include "store/format/format.hpp"
#include "tests/store/format/fixture.hpp"

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
                ("gyrocal_store_cli_" + std::to_string(::getpid())))
                   .string();
        std::filesystem::create_directories(dir_);
        db_ = dir_ + "/fixture.db";
        std::filesystem::remove(db_);
        WriteFixture(db_);
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

    static Result Run(std::vector<std::string> args) {
        args.insert(args.begin(), std::string(GYROCAL_BIN_DIR) + "/store_cli_driver");
        const std::string out = dir_ + "/out.txt", err = dir_ + "/err.txt";
        launch::ChildProcess p(args, out, err);
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
        db::Db db(db_, db::Db::Mode::kReadOnly);
        db::Stmt s(db, "SELECT count(*) FROM runs");
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
    EXPECT_EQ(
        ids(RunDb({"runs", "--json", "--since", "2026-01-21T00:00:00Z", "--outcome", "running"})),
        std::vector<std::string>{"R3"});
    const Result none = RunDb({"runs", "--since", "2030-01-01"});
    EXPECT_EQ(none.code, 0);
    EXPECT_NE(none.out.find("no runs match"), std::string::npos);
    EXPECT_EQ(ids(RunDb({"runs", "--json", "--sensor", "' OR 1=1 --"})),
              std::vector<std::string>{});
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
    for (const char* s :
         {"v1.2.3", "Plateaus (1)", "Sensitivity points (1)", "offset_v", "GYRO_S01", "(recorder)",
          "200 raw gyro samples stored", "gyrocal-plateau", "non_finite: temp_c is NaN"}) {
        EXPECT_NE(t.out.find(s), std::string::npos) << s << " missing in:\n" << t.out;
    }
}

TEST_F(StoreCli, UnknownAndHostileIdsAreAClearErrorAndChangeNothing) {
    const int64_t runs_before = RunsInDb();
    for (const std::string id :
         {"NOPE", "R1' OR '1'='1", "'; DROP TABLE runs; --", "R1\"", "%", "R_"}) {
        for (const std::vector<std::string>& cmd : {std::vector<std::string>{"show", id},
                                                    {"export", id, "--kind", "run"},
                                                    {"history", id},
                                                    {"export", id}}) {
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

std::vector<char> Bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(f), {});
}

void WriteBytes(const std::string& path, const std::vector<char>& b) {
    std::ofstream(path, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
}

// Every database entry point of the commands, on files that are not a readable gyrocal
// database: a foreign SQLite file, an empty file, a gyrocal file cut in half (a copy that
// stopped), one whose schema page is overwritten, one from a newer gyrocal. Each is one line
// naming the file and what is wrong with it, exit 1, nothing on stdout, and the file untouched.
TEST_F(StoreCli, DamagedForeignEmptyOrNewerDatabasesAreOneLineExitOneAndLeftAlone) {
    const std::vector<char> good = Bytes(db_);
    ASSERT_GT(good.size(), 32768u);
    struct Bad {
        std::string name, expect;
        std::vector<char> bytes;
    };
    std::vector<Bad> bad;
    {
        const std::string foreign = dir_ + "/foreign.db";
        db::Db db(foreign, db::Db::Mode::kReadWriteCreate);
        db.Exec("CREATE TABLE t(a); INSERT INTO t VALUES (1)");
    }
    bad.push_back({"foreign.db", "is not a gyrocal database", Bytes(dir_ + "/foreign.db")});
    bad.push_back({"empty.db", "is not a gyrocal database", {}});
    bad.push_back({"half.db", "is a damaged SQLite file",
                   std::vector<char>(good.begin(), good.begin() + good.size() / 2)});
    // The schema's page overwritten after the 100-byte file header: still an SQLite file, but
    // every statement fails (garbage elsewhere is only met by the queries that read it).
    std::vector<char> overwritten = good;
    std::fill(overwritten.begin() + 100, overwritten.begin() + 4096, '\xaa');
    bad.push_back({"overwritten.db", "is damaged", overwritten});
    std::vector<char> newer = good;
    newer[63] = 99;  // PRAGMA user_version (big-endian at byte 60): 99
    bad.push_back({"newer.db", "has schema version 99, newer than this software", newer});

    const std::vector<std::vector<std::string>> commands = {
        {"runs"},
        {"show", "R1"},
        {"history", "S01"},
        {"export", "R1", "--format", "json"},
        {"replay", "R1", "--lcm-url", "memq://"}};
    for (const Bad& b : bad) {
        const std::string path = dir_ + "/" + b.name;
        WriteBytes(path, b.bytes);
        for (auto args : commands) {
            args.insert(args.end(), {"--db", path});
            const Result r = Run(args);
            SCOPED_TRACE(b.name + ": " + args[0]);
            EXPECT_EQ(r.code, 1);
            EXPECT_EQ(Lines(r.err), 1) << r.err;
            EXPECT_NE(r.err.find(b.name), std::string::npos) << r.err;
            EXPECT_NE(r.err.find(b.expect), std::string::npos) << r.err;
            EXPECT_EQ(r.out, "");
            EXPECT_TRUE(Bytes(path) == b.bytes) << "the command changed the file";
        }
    }
}

TEST_F(StoreCli, HistoryShowsHowCoefficientsMoved) {
    const Result r = RunDb({"history", "S01", "--json", "--ref-temps-c", "0,25,50"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const auto& sets = j["coeff_sets"];
    ASSERT_EQ(sets.size(), 3u);  // final of R1, final of R2 (fitter), R2's analysis
    EXPECT_EQ(sets[0]["coeff_set_id"], 11);
    EXPECT_EQ(sets[1]["coeff_set_id"], 21);
    EXPECT_EQ(sets[2]["coeff_set_id"], 22);
    EXPECT_EQ(sets[2]["source"], "analysis:1");
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
        // The extended model through the shared evaluator at steady state: dT/dt 0, supply
        // 5 V, heating and direction 0, warmed up: every non-polynomial term contributes 0.
        const double off2 = sets[2]["at_ref_temps"][k]["offset_v"];
        const double s2 = sets[2]["at_ref_temps"][k]["sensitivity_v_per_dps"];
        EXPECT_NEAR(off2, 2.501 + 1e-3 * dT - 2e-5 * dT * dT + 3e-7 * dT * dT * dT, 1e-12);
        EXPECT_NEAR(s2, 0.0067 * 1.01 + 1e-6 * dT, 1e-15);
    }
    const Result all = RunDb({"history", "S01", "--all", "--json"});
    EXPECT_EQ(nlohmann::json::parse(all.out)["coeff_sets"].size(), 4u);
    const Result t = RunDb({"history", "S01"});
    ASSERT_EQ(t.code, 0);
    EXPECT_EQ(Lines(t.out), 1 + 2 + 3 * 3 + 3);  // title, header+rule, 3 sets x 3 temps, note
    EXPECT_NE(t.out.find("analysis:1"), std::string::npos) << t.out;
    EXPECT_EQ(t.out.find("n/a"), t.out.rfind("n/a")) << t.out;  // only in the note
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
    EXPECT_EQ(sdoc["coeff_sets"][0]["coeff_set_id"], 22);  // the newest: R2's analysis
    EXPECT_EQ(sdoc["coeff_sets"][0]["source"], "analysis:1");
    EXPECT_EQ(sdoc["coeff_sets"][0]["offset"]["term_names"][4], "dTdt");
    // A run's export: the newest set of each sensor, whatever its source.
    const Result r2 = RunDb({"export", "R2", "--format", "json"});
    ASSERT_EQ(r2.code, 0) << r2.err;
    const auto r2doc = nlohmann::json::parse(r2.out);
    ASSERT_EQ(r2doc["coeff_sets"].size(), 1u);
    EXPECT_EQ(r2doc["coeff_sets"][0]["source"], "analysis:1");
    const Result r2csv = RunDb({"export", "R2", "--format", "csv"});
    ASSERT_EQ(r2csv.code, 0);
    EXPECT_EQ(Lines(r2csv.out), 1 + 9 + 3);  // header + 9 offset + 3 sensitivity terms
    EXPECT_NE(r2csv.out.find(",analysis:1,offset,offset_v,8,warmup(600),"), std::string::npos)
        << r2csv.out;

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

TEST_F(StoreCli, ShowListsTheRunsAnalysesWithBeforeAndAfter) {
    const Result r = RunDb({"show", "R2", "--json"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["analyses"].size(), 1u);
    const auto& a = j["analyses"][0];
    EXPECT_EQ(a["analysis_id"], 1);
    EXPECT_EQ(a["sensor_id"], "S01");
    EXPECT_EQ(a["verdict"], "added temp_rate");
    EXPECT_EQ(a["candidates"].size(), 2u);
    EXPECT_EQ(a["candidates"][1]["decision"], "rejected");
    EXPECT_EQ(a["added"][0]["term"], "dTdt");
    EXPECT_EQ(a["error_before"]["rate_rms_dps"], 0.031);
    EXPECT_EQ(a["error_after"]["drift_dph"], 21.0);
    EXPECT_EQ(a["floor_rate_rms_dps"], 0.0058);
    EXPECT_EQ(a["result"]["verdict"], "added temp_rate");
    EXPECT_EQ(a["coeff_source"], "analysis:1");
    // Its set is among the run's coefficient sets, with its source.
    bool found = false;
    for (const auto& c : j["coeff_sets"]) {
        if (c["coeff_row_id"] == a["coeff_row_id"]) found = c["source"] == "analysis:1";
    }
    EXPECT_TRUE(found) << j["coeff_sets"].dump();
    EXPECT_EQ(nlohmann::json::parse(RunDb({"show", "R1", "--json"}).out)["analyses"].size(), 0u);

    const Result t = RunDb({"show", "R2"});
    ASSERT_EQ(t.code, 0);
    for (const char* s : {"Analyses (1)", "added temp_rate", "temp_rate", "0.031 -> 0.0062",
                          "95 -> 21", "0.0058", "(analysis:1)"}) {
        EXPECT_NE(t.out.find(s), std::string::npos) << s << " missing in:\n" << t.out;
    }
}

// The header carries the model path every gyrocal consumer compiles (gyrocal_model.h) verbatim,
// and each stored term as the registry resolves it (no term left unknown).
TEST_F(StoreCli, CHeaderCarriesTheSharedModelCode) {
    const Result r = RunDb({"export", "R2", "--format", "c-header"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find(std::string(model::CModelSource())), std::string::npos);
    EXPECT_EQ(r.out.find("{-1 /*"), std::string::npos) << "an unknown term kind was exported";
    EXPECT_NE(r.out.find("gyrocal_S01_tracker"), std::string::npos);
    EXPECT_NE(r.out.find("gyrocal_S01_init"), std::string::npos);
}

// Compiles `main_body` against the exported header with -Wall -Wextra -Werror and returns what
// the program printed.
std::string CompileAndRun(const std::string& dir, const std::string& header,
                          const std::string& main_body) {
    const std::string c = dir + "/use.c", exe = dir + "/use";
    std::ofstream(c) << "#include <stdio.h>\n#include \"" << header << "\"\n"
                     << "int main(void) {\n"
                     << main_body << "  return 0;\n}\n";
    launch::ChildProcess cc({"cc", "-std=c99", "-Wall", "-Wextra", "-Werror",
                             "-Wno-unused-const-variable", "-o", exe, c, "-lm"},
                            "", dir + "/cc.err");
    const auto st = cc.Wait(60s);
    EXPECT_TRUE(st && st->exited && st->code == 0) << Slurp(dir + "/cc.err");
    launch::ChildProcess run({exe}, dir + "/use.out", "");
    EXPECT_TRUE(run.Wait(10s));
    return Slurp(dir + "/use.out");
}

// The C header compiles (even with a hostile sensor id) and evaluates the models as stored.
TEST_F(StoreCli, CHeaderCompilesAndEvaluates) {
    const std::string h = dir_ + "/coeffs.h";
    ASSERT_EQ(RunDb({"export", "R1", "--format", "c-header", "--out", h}).code, 0);
    const std::string out = CompileAndRun(
        dir_, h,
        "  gyrocal_inputs_t a = gyrocal_inputs_unknown(), b = gyrocal_inputs_unknown();\n"
        "  a.temp_c = 35.0;\n"
        "  b.temp_c = 100.0;\n"
        "  printf(\"%.17g %.17g %.17g %lld\\n\", gyrocal_eval(&gyrocal_S01_offset, &a),\n"
        "         gyrocal_eval(&gyrocal_S01_sensitivity, &a),\n"
        "         gyrocal_eval(&gyrocal_S01_offset, &b),\n"
        "         (long long)GYROCAL_S01_COEFF_SET_ID);\n");
    double off = 0, sens = 0, off_clip = 0;
    long long id = 0;
    std::istringstream(out) >> off >> sens >> off_clip >> id;
    const double dT = 10.0, dT_max = 35.0;  // 35 C, and 100 C clipped to temp_max_c = 60 C
    EXPECT_NEAR(off, 2.5 + 1e-3 * dT - 2e-5 * dT * dT, 1e-12);
    EXPECT_NEAR(sens, 0.0067 + 1e-6 * dT, 1e-15);
    EXPECT_NEAR(off_clip, 2.5 + 1e-3 * dT_max - 2e-5 * dT_max * dT_max, 1e-12);
    EXPECT_EQ(id, 11);
}

// Inputs as the trackers would give them (default dT/dt time constant, sign-only branch width).
model::ModelInputs TrackedInputs(double temp_c, double dtdt, double supply_v, double heating,
                                 double direction, double since_power_s) {
    model::ModelInputs in;
    in.temp_c = temp_c;
    in.dtemp_dt_c_per_s = dtdt;
    in.rate_tau_s = GYROCAL_DEFAULT_RATE_TAU_S;
    in.supply_v = supply_v;
    in.branch = in.heating = heating;
    in.branch_width_c = GYROCAL_SIGN_BRANCH_WIDTH_C;
    in.direction = direction;
    in.time_since_power_s = since_power_s;
    return in;
}

// The extended model (every registry term kind) in C gives exactly what the C++ evaluator gives,
// for inputs on both branches and directions, out of range (clipped by default, or
// extrapolated), and with an input missing (NAN where a term needs it): both run the same code
// (gyrocal_model.h), so the values are bit-identical, not merely close.
TEST_F(StoreCli, CHeaderEvaluatesExtendedModelsLikeTheSharedEvaluator) {
    const std::string h = dir_ + "/coeffs_ext.h";
    ASSERT_EQ(RunDb({"export", "R2", "--format", "c-header", "--out", h}).code, 0);
    const std::vector<model::ModelInputs> inputs = {
        TrackedInputs(35.0, 0.01, 5.1, 1.0, -1.0, 120.0),
        TrackedInputs(100.0, -0.02, 4.9, -1.0, 1.0, 1e4),  // above the valid range
        TrackedInputs(-30.0, 0.0, 5.0, 0.3, 0.0, 0.0),     // below it; heating counts by its sign
        TrackedInputs(20.0, 0.005, NAN, 1.0, 1.0, 600.0),  // supply unknown: offset NAN
    };
    const double kGyroV = 2.6;
    std::ostringstream body;
    body << "  gyrocal_compensator_t c;\n"
         << "  gyrocal_S01_init(&c, GYROCAL_CLIP);\n";
    for (const model::ModelInputs& in : inputs) {
        auto c = [](double v) {
            if (std::isnan(v)) return std::string("NAN");
            char buf[40];
            std::snprintf(buf, sizeof buf, "%.17g", v);
            return std::string(buf);
        };
        body << "  { gyrocal_rate_t r; gyrocal_inputs_t in = gyrocal_inputs_unknown();\n"
             << "    in.temp_c = " << c(in.temp_c)
             << "; in.dtemp_dt_c_per_s = " << c(in.dtemp_dt_c_per_s)
             << "; in.rate_tau_s = GYROCAL_DEFAULT_RATE_TAU_S;\n"
             << "    in.supply_v = " << c(in.supply_v)
             << "; in.branch = in.heating = " << c(in.heating)
             << "; in.branch_width_c = GYROCAL_SIGN_BRANCH_WIDTH_C;\n"
             << "    in.direction = " << c(in.direction)
             << "; in.time_since_power_s = " << c(in.time_since_power_s) << ";\n"
             << "    r.inputs = in; gyrocal_rate_at(&c, " << c(kGyroV) << ", &r);\n"
             << "    printf(\"%.17g %.17g %.17g %.17g\\n\", gyrocal_eval(&gyrocal_S01_offset, &in),"
             << " gyrocal_eval(&gyrocal_S01_sensitivity, &in),"
             << " gyrocal_eval_policy(&gyrocal_S01_offset, &in, GYROCAL_EXTRAPOLATE, 0),"
             << " r.rate_dps); }\n";
    }
    std::istringstream out(CompileAndRun(dir_, h, body.str()));
    const model::Evaluator offset(db::ToModel(ExtendedOffset()));
    const model::Evaluator sens(db::ToModel(ExtendedSensitivity()));
    auto expect = [](double c_value, double cpp_value, const std::string& what) {
        if (std::isnan(cpp_value)) {
            EXPECT_TRUE(std::isnan(c_value)) << what << ": C gave " << c_value;
        } else {
            EXPECT_EQ(c_value, cpp_value) << what;
        }
    };
    for (size_t k = 0; k < inputs.size(); ++k) {
        std::string line;
        ASSERT_TRUE(std::getline(out, line)) << "no output for input " << k;
        std::istringstream fields(line);
        std::string f[4];
        fields >> f[0] >> f[1] >> f[2] >> f[3];
        double v[4];
        for (int i = 0; i < 4; ++i) v[i] = f[i] == "nan" || f[i] == "-nan" ? NAN : std::stod(f[i]);
        const auto& in = inputs[k];
        const auto clip = model::RangePolicy::kClip, extra = model::RangePolicy::kExtrapolate;
        const std::string at = "input " + std::to_string(k);
        expect(v[0], offset.Value(in, clip), at + " offset");
        expect(v[1], sens.Value(in, clip), at + " sensitivity");
        expect(v[2], offset.Value(in, extra), at + " offset extrapolated");
        model::ModelInputs at_rate = in;
        const double off = offset.Value(in, clip);
        at_rate.direction = kGyroV - off >= 0.0 ? 1.0 : -1.0;
        expect(v[3], (kGyroV - off) / sens.Value(at_rate, clip), at + " rate");
    }
    // The clipped and extrapolated values differ where they must (input 1 is out of range).
    EXPECT_NE(offset.Value(inputs[1], model::RangePolicy::kClip),
              offset.Value(inputs[1], model::RangePolicy::kExtrapolate));
    EXPECT_TRUE(std::isnan(offset.Value(inputs[3], model::RangePolicy::kClip)));
    EXPECT_FALSE(std::isnan(sens.Value(inputs[3], model::RangePolicy::kClip)));
}

// A stored set's JSON is the model library's writer (model/json.hpp) plus where it is stored: it
// reads back through the library's reader to the same doubles (NaN as null and back), with
// exactly the fields `gyrocal compensate --coeffs` and the export documentation name.
TEST(StoreCliJson, AStoredSetIsWrittenByTheModelWriterAndReadsBackBitForBit) {
    db::CoeffSetInfo c;
    c.coeff_row_id = 17;
    c.set.run_id = "R9";
    c.set.sensor_id = "S03";
    c.set.source = "fitter";
    c.set.coeff_set_id = 4;
    c.set.utime = 1'000'000'123;
    c.set.recv_utime = 1'000'000'456;
    c.set.plateau_ids = {1, 2, 3};
    c.set.rotation_ids = {7};
    c.set.offset = {"offset_v",
                    {"1", "dT", "dT^2"},
                    {2.5, 4.1e-4, -3.3e-6},
                    {{1e-8, 0, 0}, {0, 1e-12, 0}, {0, 0, std::nan("")}},
                    25.0,
                    -10.0,
                    60.0,
                    1.2e-5,
                    5,
                    3.3,
                    "wls"};
    c.set.sensitivity = {"sensitivity_v_per_dps",
                         {"1"},
                         {0.006},
                         {{std::nan("")}},
                         25.0,
                         -10.0,
                         60.0,
                         std::nan(""),
                         0,
                         1.0,
                         "nominal"};
    const nlohmann::json j = format::CoeffSetJson(c);
    std::vector<std::string> keys;
    for (const auto& [k, v] : j.items()) keys.push_back(k);
    EXPECT_EQ(keys, (std::vector<std::string>{"coeff_row_id", "coeff_set_id", "offset",
                                              "plateau_ids", "recv_utime", "rotation_ids", "run_id",
                                              "sensitivity", "sensor_id", "source", "utime"}));
    EXPECT_EQ(j["coeff_row_id"], 17);
    EXPECT_EQ(j["recv_utime"], 1'000'000'456);
    EXPECT_TRUE(j["offset"]["covariance"][2][2].is_null());
    const model::CoeffSet back = model::CoeffSetFromJson(nlohmann::json::parse(j.dump()));
    const model::CoeffSet want = db::ToCoeffSet(c.set);
    EXPECT_EQ(back.offset.coeffs, want.offset.coeffs);
    EXPECT_EQ(back.offset.covariance.topLeftCorner(2, 2),
              want.offset.covariance.topLeftCorner(2, 2));
    EXPECT_TRUE(std::isnan(back.offset.covariance(2, 2)));
    EXPECT_EQ(back.offset.residual_rms, 1.2e-5);
    EXPECT_TRUE(std::isnan(back.sensitivity.residual_rms));
    EXPECT_EQ(back.plateau_ids, want.plateau_ids);
    EXPECT_EQ(back.utime, want.utime);
}

}  // namespace
}  // namespace gyrocal::testing
