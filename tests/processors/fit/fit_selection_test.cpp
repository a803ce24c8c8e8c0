// Order selection: quadratic on quadratic truth, cubic on clearly cubic truth, never more terms
// than the data can carry.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/processors/fit/synth.hpp"

namespace gyrocal::fit {
namespace {

using testing::Points;
using testing::Poly;

// Under quadratic truth the cubic wins only if it lowers chi2 by more than 2 (its AIC penalty) +
// 2 (the tie margin): P(chi2_1 > 4) = 0.0455. The linear fit is never preferred over a
// quadratic this strong (b dT^2 at 35 degC is 3.7 mV, 180 sigma). So over N = 400 seeds the
// quadratic rate is ~0.954 with binomial sd sqrt(0.0455*0.954/400) = 0.0104; require >= 0.954 -
// 4*0.0104 = 0.912.
TEST(OrderSelection, PicksQuadraticOnQuadraticTruth) {
    const Poly truth{25.0, {2.5, 4e-4, 3e-6}};
    std::mt19937_64 rng(99);
    int quadratic = 0;
    constexpr int kN = 400;
    for (int k = 0; k < kN; ++k) {
        const FitResult r =
            FitPolynomial(Points(truth, {-10, 0, 12, 25, 37, 48, 60}, {2e-5}, rng), "offset_v");
        ASSERT_TRUE(r.ok()) << r.detail;
        ASSERT_EQ(r.candidates.size(), 3u);  // 7 points at 7 temperatures can carry up to cubic
        if (r.model.term_names.size() == 3) ++quadratic;
    }
    EXPECT_GE(quadratic, static_cast<int>(0.912 * kN)) << quadratic << " of " << kN;
}

// A cubic term of 2e-8 V/degC^3 is 0.86 mV at dT = 35 degC, ~40 sigma of the points: the cubic's
// chi2 improvement is ~hundreds, never below the 4 needed, on every seed.
TEST(OrderSelection, PicksCubicOnClearlyCubicTruthWithEnoughPoints) {
    const Poly truth{25.0, {2.5, 4e-4, 3e-6, 2e-8}};
    std::mt19937_64 rng(5);
    for (int k = 0; k < 50; ++k) {
        const FitResult r =
            FitPolynomial(Points(truth, {-10, 0, 12, 25, 37, 48, 60}, {2e-5}, rng), "offset_v");
        ASSERT_TRUE(r.ok()) << r.detail;
        EXPECT_EQ(r.model.term_names.size(), 4u) << r.detail;
        EXPECT_NEAR(r.model.coeffs[3], 2e-8, 4 * std::sqrt(r.model.covariance(3, 3)));
    }
}

TEST(OrderSelection, LinearAndQuadraticTieGoesToTheSeedsQuadratic) {
    // Linear truth: AIC(quadratic) - AIC(linear) = 2 - delta chi2 <= 2, always a tie by the rule.
    const Poly truth{25.0, {2.5, 4e-4}};
    std::mt19937_64 rng(8);
    const FitResult r = FitPolynomial(Points(truth, {-10, 5, 25, 40, 60}, {2e-5}, rng), "offset_v");
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.model.term_names.size(), 3u) << r.detail;
}

TEST(OrderSelection, NeverMoreTermsThanPointsMinusOneOrTemperaturesCanCarry) {
    // Cubic truth so that the criterion would always like more terms: the caps must hold.
    const Poly truth{25.0, {2.5, 4e-4, 3e-6, 2e-8}};
    std::mt19937_64 rng(17);
    struct Design {
        std::vector<double> temps;
        size_t max_terms;
    };
    const std::vector<Design> designs = {
        {{-10, 25, 60, 40}, 3},                 // 4 points: <= 3 terms
        {{-10, 25, 60, -10.2, 25.1, 59.9}, 3},  // 6 points, 3 temperatures: <= quadratic
        {{-10, 10, 30, 60, -10.1, 30.2}, 4},    // 6 points, 4 temperatures: cubic possible
        {{-10, 5, 20, 35, 60}, 4},              // 5 points, 5 temperatures
    };
    for (const Design& d : designs) {
        const FitResult r = FitPolynomial(Points(truth, d.temps, {2e-5}, rng), "offset_v");
        ASSERT_TRUE(r.ok()) << r.detail;
        EXPECT_LE(r.model.term_names.size(), d.temps.size() - 1);
        EXPECT_LE(r.model.term_names.size(), d.max_terms) << r.detail;
        for (const DegreeCandidate& c : r.candidates)
            EXPECT_LE(static_cast<size_t>(c.degree + 1), d.max_terms);
    }
    // and max_degree caps it further
    FitOptions o;
    o.max_degree = 1;
    const FitResult lin =
        FitPolynomial(Points(truth, {-10, 5, 20, 35, 60}, {2e-5}, rng), "offset_v", o);
    ASSERT_TRUE(lin.ok());
    EXPECT_EQ(lin.model.term_names.size(), 2u);
}

TEST(OrderSelection, FixedDegreeBeyondTheDataIsRefused) {
    const Poly truth{25.0, {2.5, 4e-4, 3e-6}};
    std::mt19937_64 rng(1);
    FitOptions o;
    o.fixed_degree = 3;
    const FitResult r = FitPolynomial(Points(truth, {-10, 25, 60, 40}, {2e-5}, rng), "offset_v", o);
    EXPECT_EQ(r.refusal, Refusal::kNotApplicable);
    EXPECT_NE(r.detail.find("degree 3 needs"), std::string::npos) << r.detail;
}

}  // namespace
}  // namespace gyrocal::fit
