// `gyrocal compensate`: a synthetic CSV with known truth (rate profile, offset with a dT/dt term,
// sensitivity), compensated offline from the JSON export and from the database, compared with the
// truth and with the live compensator's library on the same samples; and bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "lcmtypes/text/number.hpp"
#include "processors/compensator/compensate.hpp"
#include "store/db/model_rows.hpp"
#include "store/db/query.hpp"
#include "store/db/writer.hpp"
#include "store/format/format.hpp"
#include "tools/cli/cmd_compensate.hpp"

namespace gyrocal::analysis {
namespace {

namespace fs = std::filesystem;
namespace st = gyrocal::db;

constexpr double kRateHz = 50.0;
constexpr double kDurationS = 300.0;
constexpr double kSigmaV = 1e-3;   // [V] white noise of gyro_v
constexpr double kSigmaTC = 0.01;  // [degC] white noise of temp_c
constexpr double kRampCPerS = 1.0 / 60.0;
constexpr int64_t kStartUtime = 1'000'000'000'000'000;  // the CSV source's default

model::Model MakeModel(const std::string& quantity, std::vector<std::string> terms,
                       std::vector<double> coeffs) {
    model::Model m;
    m.quantity = quantity;
    m.term_names = std::move(terms);
    m.coeffs = Eigen::Map<Eigen::VectorXd>(coeffs.data(), static_cast<long>(coeffs.size()));
    m.covariance = Eigen::MatrixXd::Zero(m.coeffs.size(), m.coeffs.size());
    m.t0_c = 25.0;
    m.temp_min_c = 15.0;
    m.temp_max_c = 35.0;
    m.residual_rms = kSigmaV;
    m.n_points = 10;
    m.method = "analysis";
    return m;
}

// The truth: an extended model with a dT/dt term (what an analysis would publish).
model::CoeffSet TruthSet(const std::string& sensor) {
    model::CoeffSet s;
    s.utime = kStartUtime;
    s.coeff_set_id = kStartUtime;
    s.sensor_id = sensor;
    s.run_id = "R1";
    s.source = "analysis:1";
    s.offset =
        MakeModel(model::kOffsetQuantity, {"1", "dT", "dT^2", "dTdt"}, {0.01, 2e-4, 1e-6, 0.3});
    s.sensitivity = MakeModel(model::kSensitivityQuantity, {"1", "dT"}, {0.0125, -1e-5});
    return s;
}

struct Truth {
    std::vector<double> time_s, temp_c, gyro_v, rate_dps, sens_v_per_dps;
};

Truth MakeData(unsigned seed) {
    Truth t;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> nv(0.0, kSigmaV), nt(0.0, kSigmaTC);
    const model::CoeffSet set = TruthSet("S01");
    const model::Evaluator off(set.offset), sens(set.sensitivity);
    for (int i = 0; i <= static_cast<int>(kDurationS * kRateHz); ++i) {
        const double time_s = i / kRateHz;
        model::ModelInputs in;
        in.temp_c = 20.0 + kRampCPerS * time_s;
        in.dtemp_dt_c_per_s = kRampCPerS;
        in.rate_tau_s = GYROCAL_DEFAULT_RATE_TAU_S;  // what the set's bare "dTdt" means
        const double rate = 20.0 * std::sin(2 * M_PI * time_s / 30.0);
        const double s = sens.Value(in, model::RangePolicy::kClip);
        t.time_s.push_back(time_s);
        t.temp_c.push_back(in.temp_c + nt(rng));
        t.gyro_v.push_back(off.Value(in, model::RangePolicy::kClip) + s * rate + nv(rng));
        t.rate_dps.push_back(rate);
        t.sens_v_per_dps.push_back(s);
    }
    return t;
}

class CompensateCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("gyrocal_comp_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        truth_ = MakeData(4242);
        std::ofstream csv(dir_ / "data.csv");
        csv << "time_s,sensor_id,gyro_v,temp_v,temp_c\n";
        for (size_t i = 0; i < truth_.time_s.size(); ++i)
            csv << text::Sig(truth_.time_s[i], 17) << ",S01," << text::Sig(truth_.gyro_v[i], 17)
                << "," << text::Sig(2.5 + (truth_.temp_c[i] - 25.0) * 0.009, 17) << ","
                << text::Sig(truth_.temp_c[i], 17) << "\n";
        // The set stored as a recorder would keep it, and exported as `gyrocal export` does.
        db_ = (dir_ / "run.db").string();
        {
            st::StoreWriter w(db_, {"test", "host", 1});
            st::RunEventRow start;
            start.run_id = "R1";
            start.event = "start";
            start.utime = kStartUtime;
            start.sensor_ids = {"S01"};
            start.setpoint_c = NAN;
            start.recv_utime = kStartUtime;
            w.Write({start}, {});
        }
        {
            auto db = st::OpenForUpdate(db_);
            row_ = st::StoreCoeffSet(*db, TruthSet("S01"));
        }
        auto db = st::OpenForQuery(db_);
        nlohmann::json j;
        j["exported_from"] = "test";
        j["coeff_sets"] = nlohmann::json::array();
        for (const auto& s : st::RunNewestCoeffs(*db, "R1"))
            j["coeff_sets"].push_back(gyrocal::format::CoeffSetJson(s));
        std::ofstream(dir_ / "coeffs.json") << j.dump(2);
    }
    void TearDown() override { fs::remove_all(dir_); }

    cli::CompensateOptions Options() const {
        cli::CompensateOptions o;
        o.csv_path = (dir_ / "data.csv").string();
        o.coeffs_path = (dir_ / "coeffs.json").string();
        return o;
    }

    fs::path dir_;
    Truth truth_;
    std::string db_;
    int64_t row_ = 0;
};

struct OutRow {
    double time_s, rate_dps, angle_deg, temp_c;
    int range_flag;
};

std::vector<OutRow> ParseOut(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "time_s,sensor_id,rate_dps,angle_deg,temp_c,range_flag");
    std::vector<OutRow> rows;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ls(line);
        for (std::string c; std::getline(ls, c, ',');) f.push_back(c);
        EXPECT_EQ(f.size(), 6u) << line;
        if (f.size() != 6) continue;
        EXPECT_EQ(f[1], "S01");
        rows.push_back({std::stod(f[0]), std::strtod(f[2].c_str(), nullptr),
                        std::strtod(f[3].c_str(), nullptr), std::strtod(f[4].c_str(), nullptr),
                        std::stoi(f[5])});
    }
    return rows;
}

TEST_F(CompensateCli, ExportedSetRecoversTheTruthAndEqualsTheLiveCompensator) {
    std::ostringstream out, err;
    ASSERT_EQ(cli::RunCompensate(Options(), out, err), 0) << err.str();
    const std::vector<OutRow> rows = ParseOut(out.str());

    // The live compensator's library on the same samples, handed over as gyrocal-compensator
    // does: utime on the microsecond grid from the CSV source's start, seq from 0.
    compensator::SensorCompensator live;
    ASSERT_EQ(live.SetCoefficients(TruthSet("S01")).outcome, compensator::SetOutcome::kApplied);
    size_t k = 0, n_stats = 0;
    double sum_err = 0, ss_err = 0, ss_expected = 0;
    for (size_t i = 0; i < truth_.time_s.size(); ++i) {
        const auto r =
            live.Apply({kStartUtime + std::llround(truth_.time_s[i] * 1e6), static_cast<int64_t>(i),
                        truth_.gyro_v[i], truth_.temp_c[i], NAN});
        if (r.status != compensator::ApplyStatus::kOk) continue;  // not published live either
        ASSERT_LT(k, rows.size());
        // Bit-identical: the output is written with 17 significant digits.
        EXPECT_EQ(rows[k].rate_dps, r.out.rate_dps) << "sample " << i;
        EXPECT_EQ(rows[k].angle_deg, r.out.angle_deg) << "sample " << i;
        EXPECT_EQ(rows[k].range_flag, static_cast<int>(r.out.range));
        EXPECT_EQ(rows[k].temp_c, truth_.temp_c[i]);
        ++k;
        // The dT/dt tracker starts at 0 (the unit assumed at rest) and settles as
        // exp(-t / 2 tau): after 100 s (10 x 2 tau) its error is 0.3 V/(degC/s) x ramp x 2e-5.
        if (truth_.time_s[i] < 100.0) continue;
        const double e = rows[k - 1].rate_dps - truth_.rate_dps[i];
        sum_err += e;
        ss_err += e * e;
        const double sr = kSigmaV / truth_.sens_v_per_dps[i];
        ss_expected += sr * sr;
        ++n_stats;
    }
    EXPECT_EQ(k, rows.size());
    // Every sample is computed: the model inputs are defined from the first sample on.
    EXPECT_EQ(k, truth_.time_s.size());
    // Truth: the error is the gyro noise over the sensitivity, sigma_r = 1 mV / 12.5 mV/(deg/s)
    // = 0.08 deg/s per sample. The RMS of the errors after the tracker settled is within 5 % of
    // it (its relative standard deviation is 1/sqrt(2N) < 1 %; temperature noise (0.01 degC x
    // 0.2 mV/degC) and the dT/dt tracker's noise (0.3 V/(degC/s) x sigma sqrt(dt / 12 tau^3) =
    // 0.3 x 2.6e-5 degC/s) add < 0.2 %). The mean is within 5 sigma_r/sqrt(N): the tracker is
    // unbiased on a ramp. Without the dTdt term in the set the mean would be 0.3/60/0.0125 =
    // 0.4 deg/s.
    const double n = static_cast<double>(n_stats);
    const double expected_rms = std::sqrt(ss_expected / n);
    std::printf(
        "compensated %zu of %zu samples: rate error RMS %.5f deg/s (expected %.5f), mean "
        "%+.5f deg/s\n",
        k, truth_.time_s.size(), std::sqrt(ss_err / n), expected_rms, sum_err / n);
    EXPECT_NEAR(std::sqrt(ss_err / n), expected_rms, 0.05 * expected_rms);
    EXPECT_LT(std::fabs(sum_err / n), 5.0 * expected_rms / std::sqrt(n));
    EXPECT_EQ(err.str().find("not computable"), std::string::npos) << err.str();
}

TEST_F(CompensateCli, DatabaseSourcesGiveTheSameRatesAsTheExport) {
    std::ostringstream ref, err;
    ASSERT_EQ(cli::RunCompensate(Options(), ref, err), 0) << err.str();
    for (int variant = 0; variant < 3; ++variant) {
        cli::CompensateOptions o = Options();
        o.coeffs_path.clear();
        o.db = db_;
        if (variant == 0) o.run_id = "R1";
        if (variant == 1) o.sensor_id = "S01";
        if (variant == 2) o.coeff_set_row = row_;
        o.out_path = (dir_ / ("out" + std::to_string(variant) + ".csv")).string();
        std::ostringstream out;
        err.str("");
        ASSERT_EQ(cli::RunCompensate(o, out, err), 0) << variant << ": " << err.str();
        std::ifstream f(o.out_path);
        std::stringstream text;
        text << f.rdbuf();
        EXPECT_EQ(text.str(), ref.str()) << "variant " << variant;
    }
}

TEST_F(CompensateCli, BadInputFailsNamingFileLineOrField) {
    std::ostringstream out, err;
    auto run = [&](const cli::CompensateOptions& o) {
        out.str("");
        err.str("");
        return cli::RunCompensate(o, out, err);
    };
    // The file `name` holding a header and `rows` compensated.
    auto run_csv = [&](const std::string& name, const std::string& rows) {
        std::ofstream(dir_ / name) << "time_s,sensor_id,gyro_v,temp_v\n" << rows;
        cli::CompensateOptions o = Options();
        o.csv_path = (dir_ / name).string();
        return run(o);
    };
    // A sensor in the CSV without a set.
    EXPECT_EQ(run_csv("other.csv", "0,S01,2.5,2.5\n0,S02,2.5,2.5\n"), 1);
    EXPECT_NE(err.str().find("other.csv:3"), std::string::npos) << err.str();
    EXPECT_NE(err.str().find("'S02'"), std::string::npos) << err.str();
    // Malformed JSON, and a set without its offset model.
    {
        std::ofstream(dir_ / "bad.json") << "{\"coeff_sets\": [ {\"sensor_id\": ";
        cli::CompensateOptions o = Options();
        o.coeffs_path = (dir_ / "bad.json").string();
        EXPECT_EQ(run(o), 1);
        EXPECT_NE(err.str().find("bad.json: not valid JSON"), std::string::npos) << err.str();
        nlohmann::json j = nlohmann::json::parse(std::ifstream(dir_ / "coeffs.json"));
        j["coeff_sets"][0].erase("offset");
        std::ofstream(dir_ / "nooffset.json") << j.dump();
        o.coeffs_path = (dir_ / "nooffset.json").string();
        EXPECT_EQ(run(o), 1);
        EXPECT_NE(err.str().find("coeff_sets[0]"), std::string::npos) << err.str();
        EXPECT_NE(err.str().find("offset"), std::string::npos) << err.str();
    }
    // A CSV error: the producers' reader names file, line and column.
    EXPECT_EQ(run_csv("broken.csv", "0,S01,2.5,2.5\n0.01,S01,abc,2.5\n"), 1);
    EXPECT_NE(err.str().find("broken.csv"), std::string::npos) << err.str();
    EXPECT_NE(err.str().find("3"), std::string::npos) << err.str();
    EXPECT_NE(err.str().find("gyro_v"), std::string::npos) << err.str();
    EXPECT_TRUE(out.str().empty());
    // Options: two sources, none, a bad policy, an unknown stored row.
    {
        cli::CompensateOptions o = Options();
        o.db = db_;
        EXPECT_EQ(run(o), 2);
        o.db.clear();
        o.coeffs_path.clear();
        EXPECT_EQ(run(o), 2);
        o = Options();
        o.range_policy = "wrap";
        EXPECT_EQ(run(o), 2);
        EXPECT_NE(err.str().find("--out-of-range"), std::string::npos) << err.str();
        o = Options();
        o.coeffs_path.clear();
        o.db = db_;
        o.coeff_set_row = 999999;
        EXPECT_EQ(run(o), 1);
        EXPECT_NE(err.str().find("999999"), std::string::npos) << err.str();
    }
}

// The command as `gyrocal` registers it: the options reach the body (which then refuses the
// combination with exit 2), and --coeff-set-row / --temp-v-* are only set when given.
TEST(CompensateCommand, OptionsAreParsedIntoTheBody) {
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"compensate", "x.csv", "--coeffs", "a.json", "--db", "b.db"},
          std::vector<std::string>{"compensate", "x.csv", "--coeffs", "a.json", "--out-of-range",
                                   "wrap"},
          std::vector<std::string>{"compensate", "x.csv", "--coeffs", "a.json", "--coeff-set-row",
                                   "3"},
          std::vector<std::string>{"compensate", "x.csv", "--coeffs", "a.json", "--temp-v-per-c",
                                   "0"},
          // The slope's old name (hidden from --help) still reaches the body.
          std::vector<std::string>{"compensate", "x.csv", "--coeffs", "a.json", "--temp-v-per-k",
                                   "0"}}) {
        CLI::App app;
        std::function<int()> action;
        cli::AddCompensateCommand(app, action);
        std::vector<std::string> reversed(args.rbegin(), args.rend());
        ASSERT_NO_THROW(app.parse(reversed));
        ASSERT_TRUE(action) << args[3];
        EXPECT_EQ(action(), 2) << args.back();
    }
    CLI::App app;
    std::function<int()> action;
    cli::AddCompensateCommand(app, action);
    std::vector<std::string> bad = {"x", "--coeff-set-row", "x.csv", "compensate"};
    EXPECT_THROW(app.parse(bad), CLI::ParseError);
}

}  // namespace
}  // namespace gyrocal::analysis
