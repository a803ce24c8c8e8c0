// The seed's 3-point method: exact on hand-checked numbers; degenerate sets refused with the
// right reason.
#include <gtest/gtest.h>

#include <cmath>

#include "processors/fit/fit.hpp"

namespace gyrocal::fit {
namespace {

FitPoint P(double temp_c, double y, double sigma = 1e-5, int64_t id = 0) {
    FitPoint p;
    p.inputs.temp_c = temp_c;
    p.y = y;
    p.sigma_y = sigma;
    p.id = id;
    return p;
}

// Hand-checked: T = -10, 30, 60 degC, V = 2.48, 2.50, 2.53 V. With d1 = 40, d2 = 70:
//   40 a + 1600 b = 0.02,  70 a + 4900 b = 0.05
// => a = 0.0005 - 40 b;  70 (0.0005 - 40 b) + 4900 b = 0.05  => 2100 b = 0.015
// => b = 1/140000 V/degC^2 = 7.142857...e-6,  a = 0.0005 - 40/140000 = 3/14000 V/degC.
TEST(SeedThreePoint, SolvesTheSeedEquationsExactlyOnHandCheckedNumbers) {
    const FitResult r = SeedThreePoint(
        {P(-10, 2.48, 1e-5, 1), P(30, 2.50, 1e-5, 2), P(60, 2.53, 1e-5, 3)}, "offset_v");
    ASSERT_TRUE(r.ok()) << r.detail;
    const model::Model& m = r.model;
    EXPECT_EQ(m.method, "3point");
    EXPECT_EQ(m.term_names, (std::vector<std::string>{"1", "dT", "dT^2"}));
    EXPECT_EQ(m.t0_c, -10.0);      // the first point's temperature
    EXPECT_EQ(m.coeffs[0], 2.48);  // V0 itself, not a fitted value
    // "Exact to rounding": a few ulp of each value (the inputs 2.48, 2.50, 2.53 are themselves
    // rounded in binary, so 1e-12 relative is ~5000 ulp of slack, far below any method error).
    EXPECT_NEAR(m.coeffs[1], 3.0 / 14000.0, 1e-12 * 3.0 / 14000.0);
    EXPECT_NEAR(m.coeffs[2], 1.0 / 140000.0, 1e-12 * 1.0 / 140000.0);
    EXPECT_EQ(m.temp_min_c, -10.0);
    EXPECT_EQ(m.temp_max_c, 60.0);
    EXPECT_EQ(r.used_ids, (std::vector<int64_t>{1, 2, 3}));
    EXPECT_EQ(r.dof, 0);
    EXPECT_TRUE(std::isnan(r.chi2_per_dof));
    // The seed's equations hold as written.
    const double a = m.coeffs[1], b = m.coeffs[2];
    EXPECT_NEAR(2.48 + a * 40 + b * 1600, 2.50, 1e-15);
    EXPECT_NEAR(2.48 + a * 70 + b * 4900, 2.53, 1e-15);
}

TEST(SeedThreePoint, UncertaintyAtEachPointIsThatPointsStandardError) {
    // The curve passes through every point, so its value at T_k is V_k: its variance there must
    // be exactly sigma_k^2 (a check of the propagated covariance with no statistics involved).
    const double sig[3] = {1e-5, 3e-5, 2e-5};
    const FitResult r =
        SeedThreePoint({P(0, 1.0, sig[0]), P(25, 1.1, sig[1]), P(55, 1.05, sig[2])}, "offset_v");
    ASSERT_TRUE(r.ok());
    const model::Evaluator ev(r.model);
    const double temps[3] = {0, 25, 55};
    for (int k = 0; k < 3; ++k) {
        model::ModelInputs in;
        in.temp_c = temps[k];
        EXPECT_NEAR(ev.Evaluate(in, model::RangePolicy::kClip).variance, sig[k] * sig[k],
                    1e-9 * sig[k] * sig[k]);
    }
    EXPECT_NEAR(r.model.covariance(0, 0), sig[0] * sig[0], 1e-20);
}

TEST(FitPolynomial, AutoUsesTheSeedMethodForExactlyThreePointsWithT0TheFirstPoint) {
    // points deliberately not in temperature order: the seed's T0 is the first acquired
    const FitResult r = FitPolynomial(
        {P(30, 2.50, 1e-5, 7), P(-10, 2.48, 1e-5, 8), P(60, 2.53, 1e-5, 9)}, "offset_v");
    ASSERT_TRUE(r.ok()) << r.detail;
    EXPECT_EQ(r.model.method, "3point");
    EXPECT_EQ(r.model.t0_c, 30.0);
    const model::Evaluator ev(r.model);
    for (auto [t, v] : {std::pair{-10.0, 2.48}, {30.0, 2.50}, {60.0, 2.53}}) {
        model::ModelInputs in;
        in.temp_c = t;
        EXPECT_NEAR(ev.Value(in, model::RangePolicy::kClip), v, 1e-14);
    }
}

TEST(FitPolynomial, ForcedThreePointCombinesReplicatesOfALevel) {
    // Two rotations (+/-) per setpoint: each level's seed point is the weighted mean.
    FitOptions o;
    o.method = Method::kThreePoint;
    const FitResult r =
        FitPolynomial({P(-10, 0.0060, 1e-6, 1), P(-10.1, 0.0062, 1e-6, 2), P(30, 0.0061, 1e-6, 3),
                       P(30.1, 0.0061, 1e-6, 4), P(60, 0.0059, 1e-6, 5), P(60.1, 0.0059, 1e-6, 6)},
                      "sensitivity_v_per_dps", o);
    ASSERT_TRUE(r.ok()) << r.detail;
    EXPECT_EQ(r.model.method, "3point");
    EXPECT_NEAR(r.model.t0_c, -10.05, 1e-12);
    EXPECT_NEAR(r.model.coeffs[0], 0.0061, 1e-15);
    EXPECT_EQ(r.used_ids.size(), 6u);
    EXPECT_EQ(r.model.n_points, 6);
}

struct Degenerate {
    std::vector<FitPoint> points;
    Refusal want;
};

TEST(FitPolynomial, DegenerateSetsAreRefusedWithTheRightReason) {
    const std::vector<Degenerate> cases = {
        {{P(20, 1), P(40, 1.1)}, Refusal::kTooFewTemperatures},
        {{P(20, 1), P(20.3, 1.0), P(40, 1.1), P(40.2, 1.1)},
         Refusal::kTooFewTemperatures},  // 2 levels
        {{}, Refusal::kTooFewTemperatures},
        // 3 levels, but 25 and 28 are 3 degC < 5 apart: 2 temperatures carry a degree
        {{P(25, 1), P(28, 1.1), P(60, 1.2)}, Refusal::kTooFewTemperatures},
        {{P(20, 1), P(27, 1.1), P(35, 1.2)}, Refusal::kRangeTooNarrow},  // 15 degC < 20
        {{P(15, 1), P(20, 1.1), P(25, 1.2)}, Refusal::kRangeTooNarrow},  // the seed's example
        {{P(-10, 1), P(NAN, 1.1), P(60, 1.2)}, Refusal::kNonFiniteInput},
        {{P(-10, 1), P(30, INFINITY), P(60, 1.2)}, Refusal::kNonFiniteInput},
        {{P(-10, 1), P(30, 1.1, 0.0), P(60, 1.2)}, Refusal::kBadStandardError},
        {{P(-10, 1), P(30, 1.1, -1e-5), P(60, 1.2)}, Refusal::kBadStandardError},
    };
    for (size_t k = 0; k < cases.size(); ++k) {
        const FitResult r = FitPolynomial(cases[k].points, "offset_v");
        EXPECT_EQ(r.refusal, cases[k].want)
            << "case " << k << ": " << ToString(r.refusal) << ": " << r.detail;
        EXPECT_FALSE(r.detail.empty()) << "case " << k;
    }
}

TEST(FitPolynomial, RefusalThresholdsAreTheOptions) {
    const std::vector<FitPoint> pts = {P(20, 1), P(27, 1.1), P(35, 1.2)};
    FitOptions o;
    o.min_range_c = 15.0;
    EXPECT_TRUE(FitPolynomial(pts, "offset_v", o).ok());
    o.min_temp_separation_c = 7.5;  // 20 -> 27 is 7 degC: 27 adds no capacity
    EXPECT_EQ(FitPolynomial(pts, "offset_v", o).refusal, Refusal::kTooFewTemperatures);
}

TEST(FitPolynomial, ForcedMethodThatCannotApplyIsRefused) {
    FitOptions o;
    o.method = Method::kThreePoint;
    EXPECT_EQ(FitPolynomial({P(-10, 1), P(10, 1), P(30, 1), P(60, 1)}, "offset_v", o).refusal,
              Refusal::kNotApplicable);
    o = FitOptions{};
    o.max_degree = 5;
    EXPECT_EQ(FitPolynomial({P(-10, 1), P(30, 1), P(60, 1)}, "offset_v", o).refusal,
              Refusal::kNotApplicable);
}

TEST(SeedThreePoint, CoincidentTemperaturesAreIllConditionedNotNaN) {
    const FitResult r = SeedThreePoint({P(10, 1), P(10, 1.1), P(40, 1.2)}, "offset_v");
    EXPECT_EQ(r.refusal, Refusal::kIllConditioned);
    EXPECT_EQ(SeedThreePoint({P(10, 1), P(40, 1.2)}, "offset_v").refusal, Refusal::kNotApplicable);
}

}  // namespace
}  // namespace gyrocal::fit
