// `gyrocal validate` through the real CLI on a real SQLite file: a model fitted on one run of a
// unit applied to a second run of the same unit. The database holds two simulated runs of the
// same unit (seed 601, undeclared hysteresis 1 mV apart) with different noise (R2: noise seed
// 1601, started a day later), written with the store's writer as the recorder would; the model is
// the extended set `gyrocal analyze R1` stores. Then: the error on R2's still data is reported
// against R2's floor and kept in `validations`; the same model without its hysteresis term is
// reported several times worse (the figure measures the model, not the data); bad input - unknown
// run, sensor or set, a model of another unit, a run without still data - is one clear line and
// exit 1, bad options exit 2, and nothing is stored for them.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lcmtypes/launch/child_process.hpp"
#include "producers/sim/noise.hpp"
#include "store/db/writer.hpp"
#include "tests/processors/analysis/run_db.hpp"
#include "tests/processors/analysis/sim_run.hpp"
#include "tests/store/scratch_db.hpp"

namespace gyrocal::analysis {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

struct Cli {
    int code = -1;
    std::string out, err;
};

Cli Gyrocal(const std::vector<std::string>& args, const std::string& dir) {
    std::vector<std::string> argv = {GYROCAL_CLI};
    argv.insert(argv.end(), args.begin(), args.end());
    launch::ChildProcess p(argv, dir + "/cli.out", dir + "/cli.err");
    const auto st = p.Wait(120s);
    return {st ? st->code : -1, launch::ReadLog(dir + "/cli.out"),
            launch::ReadLog(dir + "/cli.err")};
}

using gyrocal::testing::Count;

class ValidateCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new std::string(::testing::TempDir() + "gyrocal_validate_" +
                               std::to_string(::getpid()));
        std::filesystem::remove_all(*dir_);
        std::filesystem::create_directories(*dir_);
        db_ = new std::string(*dir_ + "/runs.db");
        testing::SimRunOptions o;
        o.seed = 601;
        sim::SetEffect(o.effects, "hysteresis", 1e-3);
        testing::WriteSimRun(*db_, "R1", testing::MakeSimRun(o, true));
        o.noise_seed = 1601;
        o.start_utime = testing::MakeSimRun(o).config.start_utime + int64_t{86'400'000'000};
        second_ = new testing::SimRun(testing::MakeSimRun(o, true));
        testing::WriteSimRun(*db_, "R2", *second_);
        // A third run of the unit whose table never rested: every sample within a move.
        testing::SimRun moving = *second_;
        moving.raw.resize(50);
        moving.run.plateaus.clear();
        moving.run.sensitivities.clear();
        std::vector<motion::EncoderReading> spinning;
        for (const GyroSample& g : moving.raw)
            spinning.push_back({g.utime, static_cast<int64_t>(g.seq) * 100, 20000});
        moving.encoder = spinning;
        testing::WriteSimRun(*db_, "R3", moving);
        analysis_ =
            new json(json::parse(Gyrocal({"analyze", "R1", "--db", *db_, "--json"}, *dir_).out));
    }
    static void TearDownTestSuite() {
        std::filesystem::remove_all(*dir_);
        delete dir_;
        delete db_;
        delete second_;
        delete analysis_;
    }
    static std::string* dir_;
    static std::string* db_;
    static testing::SimRun* second_;
    static json* analysis_;
};
std::string* ValidateCli::dir_ = nullptr;
std::string* ValidateCli::db_ = nullptr;
testing::SimRun* ValidateCli::second_ = nullptr;
json* ValidateCli::analysis_ = nullptr;

TEST_F(ValidateCli, ModelOfOneRunOnAnotherRunOfTheUnitIsReportedAgainstItsFloorAndStored) {
    const json& a = analysis_->at("sensors").at(0);
    ASSERT_NE(a.at("added").dump().find("hysteresis"), std::string::npos) << a.dump(2);
    const Cli c = Gyrocal({"validate", "R2", "--db", *db_, "--model-run", "R1", "--json"}, *dir_);
    ASSERT_EQ(c.code, 0) << c.err;
    EXPECT_NE(c.err.find("stored as validation"), std::string::npos) << c.err;
    const json v = json::parse(c.out);
    ASSERT_EQ(v.at("sensors").size(), 1u) << c.out;
    const json& s = v.at("sensors").at(0);
    const double rms = s.at("rate_rms_dps"), floor = s.at("floor_rate_rms_dps");
    ASSERT_TRUE(std::isfinite(rms) && std::isfinite(floor)) << c.out;
    // What a right model leaves on another run of the unit: the run's own white floor, the slow
    // noise the floor cannot see (bias instability, rate random walk in bin means:
    // sim::SlowNoiseBinVariance), and the model's prediction error from R1's noise (analyze's
    // prediction_rms). Slow noise and coefficient error are each nearly one shape over the run,
    // so the 3-sigma allowance is 9x their variance.
    const double bin_s = a.at("bin_s");  // validate's default --bin-s is the analysis' bin
    const double slow2 =
        sim::SlowNoiseBinVariance(second_->config.noise, bin_s, second_->duration_s);
    const double pred = a.at("expected_after").at("prediction_rms_dps");
    EXPECT_LT(rms, std::sqrt(floor * floor + 9.0 * (slow2 + pred * pred)))
        << "floor " << floor << " slow " << std::sqrt(slow2) << " prediction " << pred;
    EXPECT_EQ(s.at("power_on"), "1 power-on record (rig)");  // the run's own, not assumed
    // Kept with the validated run, naming the model's run, with the figures printed.
    EXPECT_EQ(Count(*db_,
                    "SELECT count(*) FROM validations WHERE run_id='R2' AND sensor_id='S01' "
                    "AND model_run_id='R1'"),
              1);
    EXPECT_EQ(Count(*db_, "SELECT count(*) FROM validations WHERE run_id='R2' AND rate_rms_dps = " +
                              s.at("rate_rms_dps").dump()),
              1);

    // The same model without its hysteresis term (a JSON export, edited): the figure sees it.
    // The branch is +-0.5 mV through ~5 mV/(deg/s): ~0.1 deg/s, several floors.
    const Cli e = Gyrocal({"export", "R1", "--db", *db_, "--format", "json"}, *dir_);
    ASSERT_EQ(e.code, 0) << e.err;
    json set = json::parse(e.out);
    json& off = set.at("coeff_sets").at(0).at("offset");
    bool zeroed = false;
    for (size_t i = 0; i < off.at("term_names").size(); ++i)
        if (off.at("term_names")[i].get<std::string>().rfind("heating", 0) == 0) {
            off.at("coeffs")[i] = 0.0;
            zeroed = true;
        }
    ASSERT_TRUE(zeroed) << off.dump();
    const std::string file = *dir_ + "/no_branch.json";
    std::ofstream(file) << set.dump();
    const Cli w =
        Gyrocal({"validate", "R2", "--db", *db_, "--coeffs", file, "--json", "--no-store"}, *dir_);
    ASSERT_EQ(w.code, 0) << w.err;
    const double worse = json::parse(w.out).at("sensors").at(0).at("rate_rms_dps");
    EXPECT_GT(worse, 2.0 * rms);
    std::printf(
        "[ validate ] R1's model on R2: %.4f deg/s (floor %.4f, slow %.4f, prediction "
        "%.4f); without its branch term %.4f deg/s\n",
        rms, floor, std::sqrt(slow2), pred, worse);
    EXPECT_EQ(Count(*db_, "SELECT count(*) FROM validations"), 1);  // --no-store kept nothing
}

TEST_F(ValidateCli, BadInputIsOneClearLineAndExitOneWithNothingStored) {
    const int64_t before = Count(*db_, "SELECT count(*) FROM validations");
    // A model of another unit: the run's export with its sensor renamed.
    const Cli e = Gyrocal({"export", "R1", "--db", *db_, "--format", "json"}, *dir_);
    ASSERT_EQ(e.code, 0) << e.err;
    json other = json::parse(e.out);
    other.at("coeff_sets").at(0)["sensor_id"] = "S77";
    const std::string other_file = *dir_ + "/other_unit.json";
    std::ofstream(other_file) << other.dump();
    struct Case {
        std::vector<std::string> args;
        std::string says;
    };
    const std::vector<Case> cases = {
        {{"validate", "NOPE", "--db", *db_, "--model-run", "R1"}, "NOPE"},
        {{"validate", "R2", "--db", *db_, "--model-run", "R9"}, "R9"},
        {{"validate", "R2", "--db", *db_, "--model-run", "R1", "--sensor", "S99"}, "S99"},
        {{"validate", "R2", "--db", *db_, "--coeff-set-row", "999"}, "--coeff-set-row 999"},
        {{"validate", "R2", "--db", *db_, "--coeffs", other_file}, "no sensor of run 'R2'"},
        {{"validate", "R2", "--db", *db_, "--coeffs", *dir_ + "/missing.json"}, "missing.json"},
        {{"validate", "R3", "--db", *db_, "--model-run", "R1"}, "still"},
        {{"validate", "R2", "--db", *dir_ + "/none.db", "--model-run", "R1"}, "none.db"},
    };
    for (const Case& c : cases) {
        const Cli r = Gyrocal(c.args, *dir_);
        std::string cmd;
        for (const auto& a : c.args) cmd += a + " ";
        EXPECT_EQ(r.code, 1) << cmd << "\n" << r.err;
        EXPECT_NE(r.err.find(c.says), std::string::npos) << cmd << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << cmd << "\n" << r.err;
    }
    // Bad options: exit 2.
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"validate", "R2", "--db", *db_},
          {"validate", "R2", "--db", *db_, "--model-run", "R2"},
          {"validate", "R2", "--db", *db_, "--model-run", "R1", "--coeff-set-row", "1"},
          {"validate", "R2", "--db", *db_, "--model-run", "R1", "--bin-s", "0"}}) {
        const Cli r = Gyrocal(args, *dir_);
        EXPECT_EQ(r.code, 2) << args.back() << "\n" << r.err;
    }
    EXPECT_EQ(Count(*db_, "SELECT count(*) FROM validations"), before);
}

}  // namespace
}  // namespace gyrocal::analysis
