#include <gtest/gtest.h>

#include <cmath>

#include "tests/processors/model/test_models.hpp"

namespace gyrocal::model {
namespace {

using testing::Quadratic;

TEST(Evaluator, ValueAndVarianceAreThoseOfTheLinearModel) {
    const Model m = Quadratic();
    const Evaluator ev(m);
    ModelInputs in;
    in.temp_c = 40.0;
    const Evaluation e = ev.Evaluate(in, RangePolicy::kClip);
    const double d = 15.0;
    EXPECT_NEAR(e.value, 2.5 + 4e-4 * d + 3e-6 * d * d, 1e-15);
    // var = phi' C phi written out term by term
    const double phi[3] = {1, d, d * d};
    double var = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) var += phi[i] * m.covariance(i, j) * phi[j];
    EXPECT_NEAR(e.variance, var, 1e-12 * var);
    EXPECT_EQ(e.range, RangeFlag::kInRange);
}

TEST(Evaluator, ClipHoldsTheBoundValueExtrapolateContinuesThePolynomial) {
    const Evaluator ev(Quadratic());
    ModelInputs hot, bound;
    hot.temp_c = 80.0;
    bound.temp_c = 60.0;
    const Evaluation clipped = ev.Evaluate(hot, RangePolicy::kClip);
    const Evaluation extrap = ev.Evaluate(hot, RangePolicy::kExtrapolate);
    EXPECT_EQ(clipped.range, RangeFlag::kClipped);
    EXPECT_EQ(extrap.range, RangeFlag::kExtrapolated);
    EXPECT_DOUBLE_EQ(clipped.value, ev.Value(bound, RangePolicy::kClip));
    EXPECT_NEAR(extrap.value, 2.5 + 4e-4 * 55 + 3e-6 * 55 * 55, 1e-15);
    ModelInputs cold;
    cold.temp_c = -30.0;
    EXPECT_EQ(ev.Evaluate(cold, RangePolicy::kClip).range, RangeFlag::kClipped);
    ModelInputs edge;
    edge.temp_c = -10.0;  // the bounds themselves are in range
    EXPECT_EQ(ev.Evaluate(edge, RangePolicy::kClip).range, RangeFlag::kInRange);
}

TEST(Evaluator, NoTemperatureNoValue) {
    const Evaluator ev(Quadratic());
    EXPECT_TRUE(std::isnan(ev.Value(ModelInputs{}, RangePolicy::kClip)));
}

TEST(Evaluator, ExtendedTermsUseTheirInputs) {
    Model m = Quadratic();
    m.term_names = {"1", "dT", "dTdt"};
    m.coeffs = Eigen::Vector3d(2.5, 1e-3, 0.5);
    const Evaluator ev(m);
    ModelInputs in;
    in.temp_c = 26.0;
    in.dtemp_dt_c_per_s = 0.01;
    in.rate_tau_s = GYROCAL_DEFAULT_RATE_TAU_S;
    EXPECT_NEAR(ev.Value(in, RangePolicy::kClip), 2.5 + 1e-3 + 0.005, 1e-15);
    in.rate_tau_s = 20.0;  // tracked with another time constant than "dTdt" means: not this input
    EXPECT_TRUE(std::isnan(ev.Value(in, RangePolicy::kClip)));
    in.rate_tau_s = GYROCAL_DEFAULT_RATE_TAU_S;
    in.dtemp_dt_c_per_s = kUnknown;
    EXPECT_TRUE(std::isnan(ev.Value(in, RangePolicy::kClip)));
}

TEST(Evaluator, UnusableModelsAreRefusedNamingTheProblem) {
    auto expect_refused = [](Model m, const std::string& words) {
        testing::ExpectRefused([&] { Evaluator ev(std::move(m)); }, words);
    };
    Model m = Quadratic();
    m.term_names[2] = "dT^7";
    expect_refused(m, "unknown term 'dT^7'");
    m = Quadratic();
    m.term_names[2] = "dT";
    expect_refused(m, "appears twice");
    m = Quadratic();
    m.coeffs.resize(2);
    expect_refused(m, "coeffs has 2 values for 3 terms");
    m = Quadratic();
    m.covariance.resize(2, 2);
    expect_refused(m, "covariance is 2x2");
    m = Quadratic();
    m.coeffs[1] = NAN;
    expect_refused(m, "coefficient of 'dT' is not finite");
    m = Quadratic();
    m.temp_min_c = 70;
    expect_refused(m, "valid range");
    m = Quadratic();
    m.term_names.clear();
    m.coeffs.resize(0);
    m.covariance.resize(0, 0);
    expect_refused(m, "no terms");
}

TEST(Evaluator, NaNCovarianceMeansUnknownUncertaintyNotARefusal) {
    Model m = Quadratic();
    m.covariance.setConstant(NAN);
    const Evaluator ev(m);
    ModelInputs in;
    in.temp_c = 30;
    const Evaluation e = ev.Evaluate(in, RangePolicy::kClip);
    EXPECT_TRUE(std::isfinite(e.value));
    EXPECT_TRUE(std::isnan(e.variance));
}

TEST(RangePolicy, ParsesItsTwoNames) {
    EXPECT_EQ(ParseRangePolicy("clip"), RangePolicy::kClip);
    EXPECT_EQ(ParseRangePolicy("extrapolate"), RangePolicy::kExtrapolate);
    EXPECT_FALSE(ParseRangePolicy("wrap").has_value());
    EXPECT_STREQ(ToString(RangePolicy::kExtrapolate), "extrapolate");
}

}  // namespace
}  // namespace gyrocal::model
