// The store's bridge to the shared model library: rows <-> model::Model/CoeffSet, the
// model-typed StoreAnalysis/StoreCoeffSet the analysis calls, and the evaluation of stored models
// by THE evaluator at the steady-state inputs `gyrocal history` uses.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "processors/model/convert.hpp"
#include "processors/model/inputs.hpp"
#include "store/db/model_rows.hpp"
#include "store/db/query.hpp"
#include "store/db/writer.hpp"
#include "tests/processors/model/test_models.hpp"
#include "tests/store/row_builders.hpp"
#include "tests/store/scratch_db.hpp"

namespace gyrocal::db {
namespace {

using model::testing::ExpectSameModel;
using testing::Count;
using testing::FreshDbPath;

// Every registry term, with distinct coefficients so a swapped or dropped term shows.
model::Model Extended(const std::string& quantity) {
    model::Model m;
    m.quantity = quantity;
    m.term_names = {"1",       "dT",     "dT^2",      "dT^3",        "dTdt",
                    "heating", "supply", "direction", "warmup(600)", "dT*dTdt(5)"};
    const auto n = static_cast<Eigen::Index>(m.term_names.size());
    m.coeffs.resize(n);
    m.coeffs << 2.5, 1e-3, -2e-5, 3e-7, 0.02, 4e-4, 0.01, -3e-4, 5e-3, -7e-5;
    m.covariance = Eigen::MatrixXd::Identity(n, n) * 1e-10;
    m.covariance(0, 1) = m.covariance(1, 0) = 2e-11;
    testing::SetTestModelScalars(m, {.n_points = 40, .condition_number = 30, .method = "analysis"});
    return m;
}

model::CoeffSet ExtendedSet(const std::string& run) {
    model::CoeffSet s;
    s.utime = 123;
    s.sensor_id = "S01";
    s.run_id = run;
    s.coeff_set_id = 123;
    s.source = "to be replaced";
    s.offset = Extended(model::kOffsetQuantity);
    s.sensitivity = Extended(model::kSensitivityQuantity);
    s.plateau_ids = {1, 2, 3};
    s.rotation_ids = {4};
    return s;
}

TEST(ModelRows, RoundTripThroughRows) {
    const model::Model m = Extended(model::kOffsetQuantity);
    ExpectSameModel(ToModel(ToModelRow(m)), m);
    const model::CoeffSet s = ExtendedSet("R1");
    const model::CoeffSet back = ToCoeffSet(ToCoeffSetRow(s, 77));
    ExpectSameModel(back.offset, s.offset);
    EXPECT_EQ(back.plateau_ids, s.plateau_ids);
    EXPECT_EQ(ToCoeffSetRow(s, 77).recv_utime, 77);
}

TEST(ModelRows, SteadyStateValueIsTheSharedEvaluatorAtSteadyInputs) {
    const ModelRow row = ToModelRow(Extended(model::kOffsetQuantity));
    // At steady state (dT/dt 0, 5 V, between branches and directions, warmed up) only the
    // polynomial part remains: 2.5 + 1e-3 dT - 2e-5 dT^2 + 3e-7 dT^3.
    for (double temp_c : {-10.0, 0.0, 25.0, 37.5, 60.0, 80.0 /* extrapolated */}) {
        const double dT = temp_c - 25;
        const double want = 2.5 + 1e-3 * dT - 2e-5 * dT * dT + 3e-7 * dT * dT * dT;
        const auto got = SteadyStateValue(row, temp_c);
        ASSERT_TRUE(got);
        EXPECT_NEAR(*got, want, 1e-15 * 4);  // a few ulps of 2.5
        EXPECT_EQ(*got,
                  model::Evaluate(ToModel(row), model::SteadyStateInputs(ToModel(row), temp_c),
                                  model::RangePolicy::kExtrapolate)
                      .value);
    }
    // Not usable: unknown term, no terms, non-finite range.
    ModelRow bad = row;
    bad.term_names[4] = "humidity";
    EXPECT_FALSE(SteadyStateValue(bad, 25));
    EXPECT_FALSE(SteadyStateValue(ModelRow{}, 25));
    bad = row;
    bad.temp_max_c = std::nan("");
    EXPECT_FALSE(SteadyStateValue(bad, 25));
}

// The fixtures' polynomial model (row_builders.hpp) is the polynomial it names: with the test
// model's range, the shared evaluator gives c0 + c1 dT + c2 dT^2 (to a few ulps of 2.5).
TEST(ModelRows, FixturesPolynomialModelIsThePolynomialItNames) {
    ModelRow row = testing::PolynomialModel(model::kOffsetQuantity, {2.5, 1e-3, -2e-5});
    testing::SetTestModelScalars(row);
    EXPECT_EQ(row.term_names, (std::vector<std::string>{"1", "dT", "dT^2"}));
    ASSERT_EQ(row.covariance.size(), 3u);
    EXPECT_EQ(row.covariance[2], (std::vector<double>{0.0, 0.0, 0.0}));
    for (double temp_c : {-10.0, 25.0, 60.0}) {
        const double dT = temp_c - 25;
        const auto got = SteadyStateValue(row, temp_c);
        ASSERT_TRUE(got);
        EXPECT_NEAR(*got, 2.5 + 1e-3 * dT - 2e-5 * dT * dT, 1e-15 * 4);
    }
    EXPECT_EQ(testing::PolynomialModel("offset_v", {2.5}).term_names,
              (std::vector<std::string>{"1"}));
}

TEST(ModelRows, StoreAnalysisWithAModelCoeffSetAndWithAMessage) {
    const std::string path = FreshDbPath("model_rows.db");
    StoreWriter w(path, {"test", "h", 1});
    w.Write({testing::RunEvent("R1", "start", {}, 1)}, {});
    Db& db = w.db();

    AnalysisRow a;
    a.run_id = "R1";
    a.sensor_id = "S01";
    a.created_wall_utime = 1000;
    const model::CoeffSet set = ExtendedSet("R1");
    const StoredAnalysis s1 = StoreAnalysis(db, a, &set);
    ASSERT_TRUE(s1.coeff_row_id);
    EXPECT_EQ(s1.source, AnalysisSource(s1.analysis_id));
    // Read back through the queries: the whole model, with the analysis as its source.
    const auto history = SensorHistory(db, "S01", false);
    ASSERT_EQ(history.size(), 1u);
    EXPECT_EQ(history[0].coeff_row_id, *s1.coeff_row_id);
    const model::CoeffSet back = ToCoeffSet(history[0].set);
    EXPECT_EQ(back.source, s1.source);
    EXPECT_EQ(back.run_id, "R1");
    ExpectSameModel(back.offset, set.offset);
    ExpectSameModel(back.sensitivity, set.sensitivity);
    EXPECT_EQ(back.rotation_ids, set.rotation_ids);

    // The coeff_set_t overload (what is published) stores the same.
    const gyrocal::coeff_set_t msg = model::ToMsg(set);
    const StoredAnalysis s2 = StoreAnalysis(db, a, &msg);
    ASSERT_TRUE(s2.coeff_row_id);
    EXPECT_NE(*s2.coeff_row_id, *s1.coeff_row_id);  // another analysis, another source
    // Stored directly under a given source; a repeat returns the same row.
    const int64_t direct = StoreCoeffSet(db, msg, 2000);
    EXPECT_EQ(StoreCoeffSet(db, set, 3000), direct);

    // An unusable model is refused before anything is written.
    model::CoeffSet bad = set;
    bad.offset.coeffs[5] = std::nan("");
    const int64_t analyses = Count(db, "SELECT count(*) FROM analyses");
    const int64_t sets = Count(db, "SELECT count(*) FROM coeff_sets");
    EXPECT_THROW(StoreAnalysis(db, a, &bad), model::ModelError);
    EXPECT_THROW(StoreCoeffSet(db, bad), model::ModelError);
    gyrocal::coeff_set_t bad_msg = msg;
    bad_msg.offset.num_terms = 3;  // lengths no longer agree
    EXPECT_THROW(StoreAnalysis(db, a, &bad_msg), model::ModelError);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM analyses"), analyses);
    EXPECT_EQ(Count(db, "SELECT count(*) FROM coeff_sets"), sets);
}

}  // namespace
}  // namespace gyrocal::db
