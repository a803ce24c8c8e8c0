// Overdispersion (fit.hpp): points whose real errors are k = 2 times the stated ones (the
// plateaus' window misses slow noise). Order selection must be no worse than with honest errors,
// and the Birge-scaled covariance must be calibrated.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "processors/fit/fit_util.hpp"
#include "tests/processors/fit/synth.hpp"

namespace gyrocal::fit {
namespace {

using testing::Poly;

const Poly kQuadTruth{25.0, {2.5, 4e-4, 3e-6}};
const double kAlpha = std::erfc(std::sqrt(2.0));  // P(chi2_1 > 4): AIC's known-variance rate

// Points with stated error sigma_stated and real error k * sigma_stated, from a given N(0,1) draw
// so that honest (k = 1) and understated (k = 2) sets share the noise pattern.
std::vector<FitPoint> Scaled(const Poly& truth, const std::vector<double>& temps,
                             double sigma_stated, double k, const std::vector<double>& z) {
    std::vector<FitPoint> pts;
    for (size_t i = 0; i < temps.size(); ++i) {
        FitPoint p;
        p.inputs.temp_c = temps[i];
        p.sigma_y = sigma_stated;
        p.y = truth(temps[i]) + k * sigma_stated * z[i];
        p.id = static_cast<int64_t>(i);
        pts.push_back(p);
    }
    return pts;
}

std::vector<double> Draw(size_t n, std::mt19937_64& rng) {
    std::normal_distribution<double> n01;
    std::vector<double> z(n);
    for (double& v : z) v = n01(rng);
    return z;
}

TEST(Overdispersion, TieBandIsTheFQuantileThatKeepsAicsErrorRate) {
    // F(1, nu) = t_nu^2; t_1 and t_2 have closed-form quantiles; F(1, inf) = chi2_1, whose
    // 1 - kAlpha quantile is exactly 4.
    const double p = 1.0 - kAlpha / 2.0;
    EXPECT_NEAR(detail::FOneUpperQuantile(kAlpha, 1), std::pow(std::tan(M_PI * (p - 0.5)), 2),
                1e-8 * 195);
    EXPECT_NEAR(detail::FOneUpperQuantile(kAlpha, 2),
                std::pow((2 * p - 1) / std::sqrt(2 * p * (1 - p)), 2), 1e-8 * 20);
    EXPECT_NEAR(detail::FOneUpperQuantile(kAlpha, 100000), 4.0, 1e-3);  // O(1/nu) from the limit
}

// GIVEN a quadratic truth measured at the 7 temperatures of the honest-error selection test and
// at the 5 of the default profile, with the noise draw shared between stated errors that are
// honest (k = 1) and understated twofold (k = 2)
// THEN the quadratic is chosen at least as often with k = 2 as with k = 1, and at AIC's rate.
// Derivation: with c estimated on nu dof, (chi2 drop)/c is F(1, nu) under the quadratic and the
// band keeps P(cubic) = kAlpha = 0.0455 whatever k (with c' = max(1, c) the rate is lower still
// when c < 1, which happens more often with k = 1). Over N = 400 draws the count of cubics has
// binomial sd sqrt(N kAlpha (1 - kAlpha)) = 4.2: the quadratic count must be >= N (1 - kAlpha) -
// 4 sd, and the k = 2 count >= the k = 1 count - 4 sqrt(2) sd (two such counts, worst case
// independent). Before the overdispersion the 7-point k = 2 case chose the cubic whenever the
// chi2 drop exceeded 4 with real errors 2x the stated: P(chi2_1 > 1) = 0.32 (count ~272 of 400).
TEST(Overdispersion, UnderstatedErrorsChooseTheOrderNoWorseThanHonestOnes) {
    constexpr int kN = 400;
    const double sd = std::sqrt(kN * kAlpha * (1 - kAlpha));
    const std::vector<std::vector<double>> designs = {{-10, 0, 12, 25, 37, 48, 60},
                                                      {-40, -10, 25, 55, 85}};
    for (const std::vector<double>& temps : designs) {
        std::mt19937_64 rng(321);
        int quadratic[2] = {0, 0};
        for (int n = 0; n < kN; ++n) {
            const std::vector<double> z = Draw(temps.size(), rng);
            for (int k : {1, 2}) {
                const FitResult r =
                    FitPolynomial(Scaled(kQuadTruth, temps, 2e-5, k, z), "offset_v");
                ASSERT_TRUE(r.ok()) << r.detail;
                ASSERT_EQ(r.overdispersion_dof, static_cast<int>(temps.size()) - 4);
                if (r.model.term_names.size() == 3) ++quadratic[k - 1];
            }
        }
        EXPECT_GE(quadratic[0], kN * (1 - kAlpha) - 4 * sd) << temps.size() << " points";
        EXPECT_GE(quadratic[1], kN * (1 - kAlpha) - 4 * sd) << temps.size() << " points";
        EXPECT_GE(quadratic[1], quadratic[0] - 4 * std::sqrt(2.0) * sd) << temps.size();
    }
}

// The default profile's five points leave one dof; pooled with three other units (one dof each,
// as the fitter pools a 4-unit run) c has nu = 4 and the band is F(1,4) - 2 = 6.2.
// GIVEN a real cubic of 2e-8 V/degC^3 and stated errors 2x too small
// THEN the cubic is chosen on every draw. Derivation: lambda = chi2 of the noise-free quadratic fit
// in REAL error units (computed below, required >= 400) is the non-centrality of the drop; the
// drop/c is then >= (sqrt(lambda) - 4)^2 / (chi2_4/4) >= 256 / (chi2_4 / 4), above F = 8.2
// unless chi2_4 > 125 (probability ~1e-25). And on quadratic truth with the same pooling the
// quadratic rate is AIC's (binomial bound as above).
TEST(Overdispersion, PooledEvidenceFindsARealCubicOnFivePoints) {
    const std::vector<double> temps = {-40, -10, 25, 55, 85};
    const Poly cubic{25.0, {2.5, 4e-4, 3e-6, 2e-8}};
    const double sigma_stated = 3e-5, k = 2.0;
    std::vector<FitPoint> exact = Scaled(cubic, temps, k * sigma_stated, 0.0, {0, 0, 0, 0, 0});
    const FitResult q = FitWls(exact, model::PolynomialTerms(2), 25.0, "offset_v");
    ASSERT_TRUE(q.ok());
    ASSERT_GE(q.chi2, 400.0) << "the cubic is too weak for this test's derivation";
    constexpr int kN = 200;
    std::mt19937_64 rng(77);
    int cubic_chosen = 0, quadratic_on_quadratic = 0;
    for (int n = 0; n < kN; ++n) {
        FitOptions o;
        for (int u = 0; u < 3; ++u) {  // three other units: reference chi2 of their own cubic
            const FitResult other = FitPolynomial(
                Scaled(kQuadTruth, temps, sigma_stated, k, Draw(temps.size(), rng)), "offset_v");
            ASSERT_TRUE(other.ok());
            ASSERT_EQ(other.reference_dof, 1);
            o.pooled_chi2 += other.reference_chi2;
            o.pooled_dof += other.reference_dof;
        }
        const std::vector<double> z = Draw(temps.size(), rng);
        const FitResult c = FitPolynomial(Scaled(cubic, temps, sigma_stated, k, z), "offset_v", o);
        ASSERT_TRUE(c.ok()) << c.detail;
        EXPECT_EQ(c.overdispersion_dof, 4);
        if (c.model.term_names.size() == 4) ++cubic_chosen;
        const FitResult r =
            FitPolynomial(Scaled(kQuadTruth, temps, sigma_stated, k, z), "offset_v", o);
        if (r.model.term_names.size() == 3) ++quadratic_on_quadratic;
    }
    EXPECT_EQ(cubic_chosen, kN);
    EXPECT_GE(quadratic_on_quadratic,
              kN * (1 - kAlpha) - 4 * std::sqrt(kN * kAlpha * (1 - kAlpha)));
}

// GIVEN 40 points (8 temperatures x 5) over -40..85 degC with stated errors half the real ones,
// fitted with the quadratic (degree fixed: the calibration of a covariance is a property of one
// model; after order selection the rare cubics chosen BECAUSE the noise looked cubic have a
// selection-biased slope, whatever the covariance)
// THEN the Birge-scaled covariance is calibrated: z_j = (est_j - true_j) / sqrt(C_jj) over N = 500
// draws. c is the fit's chi2/dof on nu = 37 dof, so z is Student-t with 37 dof: std
// sqrt(nu/(nu-2)) = 1.028, excess kurtosis 6/(nu-4) = 0.18; the sample std of N such values has
// sd sqrt((kurtosis - 1)/(4N)) = 0.033; 4 of those is the tolerance. Unscaled, the std would be
// k = 2 (the test fails a covariance off by ~13 % or more).
TEST(Overdispersion, BirgeScaledCovarianceIsCalibratedOver500Seeds) {
    constexpr int kN = 500;
    std::vector<double> temps;
    for (int i = 0; i < 8; ++i)  // 8 setpoints, 5 plateaus each (replicates of a level)
        for (int j = 0; j < 5; ++j) temps.push_back(-40.0 + 125.0 * i / 7.0 + 0.1 * j);
    const double nu = 37.0;
    const double expected_std = std::sqrt(nu / (nu - 2.0));
    const double kurtosis = 3.0 + 6.0 / (nu - 4.0);
    const double tol = 4.0 * std::sqrt((kurtosis - 1.0) / (4.0 * kN));
    FitOptions quadratic;
    quadratic.fixed_degree = 2;
    std::mt19937_64 rng(2718);
    testing::ZScores z(3);
    double c_sum = 0;
    for (int n = 0; n < kN; ++n) {
        const FitResult r = FitPolynomial(
            Scaled(kQuadTruth, temps, 2e-5, 2.0, Draw(temps.size(), rng)), "offset_v", quadratic);
        ASSERT_TRUE(r.ok()) << r.detail;
        ASSERT_EQ(r.overdispersion_dof, 37);
        EXPECT_EQ(r.covariance_scale, std::max(1.0, r.overdispersion));
        c_sum += r.overdispersion;
        z.Add(r, kQuadTruth);
    }
    for (size_t j = 0; j < 3; ++j) {
        EXPECT_NEAR(z.Std(j), expected_std, tol) << "coefficient " << j;
        EXPECT_NEAR(z.Mean(j), 0.0, 4.0 * expected_std / std::sqrt(kN)) << "coefficient " << j;
    }
    // c estimates k^2 = 4: the mean of 4 chi2_37/37 over N has sd 4 sqrt(2/37/N) = 0.042.
    EXPECT_NEAR(c_sum / kN, 4.0, 4 * 4.0 * std::sqrt(2.0 / 37.0 / kN));
}

// With the order chosen on evidence, c comes from the cubic reference (nu = 36) whatever order
// is chosen, and estimates k^2 without bias (same bound as above with 36 dof).
TEST(Overdispersion, ChosenOrderUsesTheLargestCandidatesOverdispersion) {
    constexpr int kN = 500;
    std::vector<double> temps;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 5; ++j) temps.push_back(-40.0 + 125.0 * i / 7.0 + 0.1 * j);
    std::mt19937_64 rng(31415);
    double c_sum = 0;
    for (int n = 0; n < kN; ++n) {
        const FitResult r = FitPolynomial(
            Scaled(kQuadTruth, temps, 2e-5, 2.0, Draw(temps.size(), rng)), "offset_v");
        ASSERT_TRUE(r.ok()) << r.detail;
        ASSERT_EQ(r.overdispersion_dof, 36);
        ASSERT_EQ(r.candidates.back().degree, 3);
        EXPECT_DOUBLE_EQ(r.overdispersion, r.candidates.back().chi2 / 36.0);
        EXPECT_DOUBLE_EQ(r.covariance_scale, std::max(1.0, r.overdispersion));
        c_sum += r.overdispersion;
    }
    EXPECT_NEAR(c_sum / kN, 4.0, 4 * 4.0 * std::sqrt(2.0 / 36.0 / kN));
}

TEST(Overdispersion, WithoutDofTheStatedErrorsStand) {
    // GIVEN 3 points (the seed's solution, no dof) with understated errors
    std::mt19937_64 rng(4);
    const std::vector<FitPoint> pts = Scaled(kQuadTruth, {-10, 30, 60}, 2e-5, 2.0, Draw(3, rng));
    const FitResult r = FitPolynomial(pts, "offset_v");
    ASSERT_TRUE(r.ok());
    // THEN nothing is estimated or scaled: the covariance is the seed solution's own
    EXPECT_TRUE(std::isnan(r.overdispersion));
    EXPECT_EQ(r.overdispersion_dof, 0);
    EXPECT_EQ(r.covariance_scale, 1.0);
    const FitResult seed = SeedThreePoint(pts, "offset_v");
    EXPECT_TRUE(r.model.covariance.isApprox(seed.model.covariance, 1e-12));
}

TEST(Overdispersion, BadPooledEvidenceIsRefusedNamingIt) {
    FitOptions o;
    o.pooled_dof = -1;
    EXPECT_NE(o.Validate().find("pooled"), std::string::npos);
    o.pooled_dof = 0;
    o.pooled_chi2 = 3.0;
    EXPECT_NE(o.Validate().find("pooled"), std::string::npos);
    o.pooled_dof = 2;
    o.pooled_chi2 = NAN;
    EXPECT_NE(o.Validate().find("pooled"), std::string::npos);
    o.pooled_chi2 = 3.0;
    EXPECT_EQ(o.Validate(), "");
}

}  // namespace
}  // namespace gyrocal::fit
