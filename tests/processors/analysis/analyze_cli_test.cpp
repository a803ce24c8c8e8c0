// `gyrocal analyze` over a database: a simulated run with an undeclared effect is written with
// the store's writer (as the recorder would), then analysed through the command body.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "analyses.hpp"
#include "cmd_analyze.hpp"
#include "query.hpp"
#include "sim_run.hpp"
#include "writer.hpp"

namespace gyrocal::analysis {
namespace {

namespace st = gyrocal::store;

std::string WriteRunDb(const std::string& name) {
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("gyrocal_analysis_cli_" + std::to_string(::getpid()) + "_" + name))
                                 .string();
    std::filesystem::remove(path);
    testing::SimRunOptions o;
    o.seed = 601;
    sim::SetEffect(o.effects, "hysteresis", 1e-3);
    const testing::SimRun s = testing::MakeSimRun(o, true);
    st::StoreWriter w(path, {"test", "host", 1});
    std::vector<st::Row> rows;
    st::RunEventRow start;
    start.run_id = "R1";
    start.event = "start";
    start.utime = s.raw.front().utime;
    start.sensor_ids = {"S01"};
    start.setpoint_c = NAN;
    start.recv_utime = start.utime;
    rows.push_back(start);
    for (const GyroSample& g : s.raw) {
        st::GyroRow r;
        r.run_id = "R1";
        r.sensor_id = "S01";
        r.utime = g.utime;
        r.seq = g.seq;
        r.gyro_v = g.gyro_v;
        r.temp_c = g.temp_c;
        r.temp_v = NAN;
        r.supply_v = g.supply_v;
        r.recv_utime = g.utime;
        rows.push_back(r);
    }
    int64_t seq = 0;
    for (const EncoderSample& e : s.encoder) {
        st::EncoderRow r;
        r.run_id = "R1";
        r.encoder_id = "E";
        r.utime = e.utime;
        r.seq = seq++;
        r.angle_deg = e.angle_deg;
        r.recv_utime = e.utime;
        rows.push_back(r);
    }
    for (const PlateauInput& p : s.run.plateaus) {
        st::PlateauRow r;
        r.run_id = "R1";
        r.sensor_id = "S01";
        r.plateau_id = p.plateau_id;
        r.utime = p.end_utime;
        r.start_utime = p.start_utime;
        r.end_utime = p.end_utime;
        r.n_samples = static_cast<int32_t>(p.n_samples);
        r.temp_mean_c = p.temp_mean_c;
        r.temp_sem_c = p.temp_sem_c;
        r.gyro_mean_v = p.gyro_mean_v;
        r.gyro_sem_v = p.gyro_sem_v;
        r.recv_utime = p.end_utime;
        rows.push_back(r);
    }
    for (const SensitivityInput& si : s.run.sensitivities) {
        st::SensitivityRow r;
        r.run_id = "R1";
        r.sensor_id = "S01";
        r.rotation_id = si.rotation_id;
        r.utime = si.utime;
        r.direction = si.direction;
        r.temp_c = si.temp_c;
        r.sensitivity_v_per_dps = si.sensitivity_v_per_dps;
        r.sensitivity_stderr_v_per_dps = si.stderr_v_per_dps;
        r.accepted = true;
        r.recv_utime = si.utime;
        rows.push_back(r);
    }
    w.Write(rows, {});
    return path;
}

class AnalyzeCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() { path_ = new std::string(WriteRunDb("hyst.db")); }
    static void TearDownTestSuite() {
        std::filesystem::remove(*path_);
        delete path_;
    }
    static std::string* path_;
};
std::string* AnalyzeCli::path_ = nullptr;

TEST_F(AnalyzeCli, FindsTheEffectInTheRecordedRunAsJson) {
    cli::AnalyzeOptions o;
    o.run_id = "R1";
    o.db = *path_;
    o.json = true;
    std::ostringstream out, err;
    ASSERT_EQ(cli::RunAnalyze(o, out, err), 0) << err.str();
    const nlohmann::json j = nlohmann::json::parse(out.str());
    ASSERT_EQ(j["sensors"].size(), 1u);
    EXPECT_EQ(j["sensors"][0]["sensor_id"], "S01");
    EXPECT_EQ(j["sensors"][0]["verdict"], "missing effect: hysteresis") << out.str();
    ASSERT_EQ(j["sensors"][0]["added"].size(), 1u);
    // Truth 0.5 mV; 4 stderr + 5 % (see discovery_test.cpp for the allowance).
    const double c = j["sensors"][0]["added"][0]["coefficient"],
                 se = j["sensors"][0]["added"][0]["stderr"];
    EXPECT_NEAR(c, 0.5e-3, 4 * se + 0.05 * 0.5e-3);
    // Kept with the run: the analysis row and the extended model with its provenance.
    auto db = st::OpenForQuery(*path_);
    const std::vector<st::AnalysisRow> kept = st::ListAnalyses(*db, "R1");
    ASSERT_EQ(kept.size(), 1u);
    EXPECT_EQ(kept[0].verdict, "missing effect: hysteresis");
    ASSERT_TRUE(kept[0].coeff_row_id.has_value());
    const st::RunDetail d = st::ShowRun(*db, "R1");
    ASSERT_EQ(d.coeff_sets.size(), 1u);
    EXPECT_EQ(d.coeff_sets[0].set.source, "analysis:" + std::to_string(kept[0].analysis_id));
    EXPECT_NE(std::find(d.coeff_sets[0].set.offset.term_names.begin(),
                        d.coeff_sets[0].set.offset.term_names.end(), "heating"),
              d.coeff_sets[0].set.offset.term_names.end());
}

TEST_F(AnalyzeCli, NoStoreLeavesTheDatabaseAlone) {
    cli::AnalyzeOptions o;
    o.run_id = "R1";
    o.db = *path_;
    o.store = false;
    std::ostringstream out, err;
    auto db = st::OpenForQuery(*path_);
    const size_t before = st::ListAnalyses(*db, "R1").size();
    ASSERT_EQ(cli::RunAnalyze(o, out, err), 0) << err.str();
    EXPECT_NE(out.str().find("sensor S01: missing effect: hysteresis"), std::string::npos)
        << out.str();
    EXPECT_EQ(st::ListAnalyses(*db, "R1").size(), before);
}

TEST_F(AnalyzeCli, UnknownRunSensorOrDatabaseFailsWithTheReason) {
    cli::AnalyzeOptions o;
    o.run_id = "nope";
    o.db = *path_;
    std::ostringstream out, err;
    EXPECT_EQ(cli::RunAnalyze(o, out, err), 1);
    EXPECT_NE(err.str().find("nope"), std::string::npos) << err.str();
    o.run_id = "R1";
    o.sensor_id = "S99";
    err.str("");
    EXPECT_EQ(cli::RunAnalyze(o, out, err), 1);
    EXPECT_NE(err.str().find("S99"), std::string::npos) << err.str();
    o.sensor_id = "";
    o.db = *path_ + ".missing";
    err.str("");
    EXPECT_EQ(cli::RunAnalyze(o, out, err), 1);
    EXPECT_FALSE(err.str().empty());
    o.db = *path_;
    o.holdout_fraction = 0.99;
    err.str("");
    EXPECT_EQ(cli::RunAnalyze(o, out, err), 2);
    EXPECT_NE(err.str().find("holdout_fraction"), std::string::npos) << err.str();
}

}  // namespace
}  // namespace gyrocal::analysis
