// Weighted least squares: recovery of known coefficients within k sigma of the reported
// covariance, and a calibration of the reported uncertainty itself over many seeds.
#include <gtest/gtest.h>

#include <cmath>

#include "processors/model/terms.hpp"
#include "tests/processors/fit/synth.hpp"

namespace gyrocal::fit {
namespace {

using testing::Points;
using testing::Poly;

const Poly kQuadTruth{25.0, {2.5, 4e-4, 3e-6}};
const std::vector<double> kTemps = {-10, 0, 12, 25, 37, 48, 60};
// Heteroscedastic standard errors (plateaus of different length/noise) exercise the weights.
const std::vector<double> kSigmas = {2e-5, 1e-5, 3e-5, 1.5e-5, 2.5e-5, 1e-5, 2e-5};

FitOptions Quadratic() {
    FitOptions o;
    o.fixed_degree = 2;
    return o;
}

TEST(FitWls, RecoversKnownCoefficientsWithinFourSigmaOfTheReportedCovariance) {
    std::mt19937_64 rng(42);
    const FitResult r =
        FitPolynomial(Points(kQuadTruth, kTemps, kSigmas, rng), "offset_v", Quadratic());
    ASSERT_TRUE(r.ok()) << r.detail;
    EXPECT_EQ(r.model.method, "wls");
    EXPECT_EQ(r.model.t0_c, 25.0);  // midpoint of -10..60, a multiple of 5
    // If the covariance is right, each error is N(0, sigma_j); 4 sigma is exceeded with
    // probability 6e-5 per coefficient, and the uncertainty test below checks the sigma itself.
    for (int j = 0; j < 3; ++j)
        EXPECT_NEAR(r.model.coeffs[j], kQuadTruth.c[static_cast<size_t>(j)],
                    4 * std::sqrt(r.model.covariance(j, j)))
            << "coefficient " << j;
    EXPECT_EQ(r.dof, 4);
    EXPECT_EQ(r.residuals.size(), 7);
    EXPECT_EQ(r.used_ids.size(), 7u);
    EXPECT_LT(r.model.condition_number, 10.0);  // centred, scaled columns: near orthogonal
    EXPECT_GT(r.model.residual_rms, 0.0);
    // The covariance is symmetric positive definite.
    EXPECT_TRUE(r.model.covariance.isApprox(r.model.covariance.transpose(), 0));
    EXPECT_EQ(r.model.covariance.llt().info(), Eigen::Success);
}

TEST(FitWls, NoiseFreeDataIsReproducedToRounding) {
    std::vector<FitPoint> pts;
    for (double t : kTemps) {
        FitPoint p;
        p.inputs.temp_c = t;
        p.y = kQuadTruth(t);
        p.sigma_y = 1e-5;
        pts.push_back(p);
    }
    const FitResult r = FitWls(pts, model::PolynomialTerms(2), 25.0, "offset_v");
    ASSERT_TRUE(r.ok());
    // 1e-13 V relative to 2.5 V values: ~200 ulp after a QR of a well-conditioned 7x3 system.
    EXPECT_NEAR(r.model.coeffs[0], 2.5, 1e-13);
    EXPECT_NEAR(r.model.coeffs[1], 4e-4, 1e-15);
    EXPECT_NEAR(r.model.coeffs[2], 3e-6, 1e-16);
    EXPECT_LT(r.chi2, 1e-12);
}

// Calibration of the uncertainty: over N independent noise draws the normalised errors
// z_j = (est_j - true_j) / sqrt(C_jj) must be N(0,1) if the covariance is right. For N = 500 the
// sample standard deviation s of N(0,1) values has standard deviation 1/sqrt(2(N-1)) = 0.0317
// (chi distribution, large-N), so |s - 1| < 4 * 0.0317 = 0.127 fails a correct covariance with
// probability 6e-5 per coefficient, but fails a covariance off by 15% or more. The mean of z has
// standard deviation 1/sqrt(N) = 0.0447: |mean| < 0.18 (4 sigma). chi2 per fit has mean dof = 4
// and variance 2 dof = 8, so the mean over N has sd sqrt(8/500) = 0.126: |mean - 4| < 0.51.
TEST(FitWls, ReportedCovarianceMatchesTheScatterOver500Seeds) {
    constexpr int kN = 500;
    std::mt19937_64 rng(2024);
    testing::ZScores z(3);
    double chi2_sum = 0;
    for (int k = 0; k < kN; ++k) {
        const FitResult r =
            FitPolynomial(Points(kQuadTruth, kTemps, kSigmas, rng), "offset_v", Quadratic());
        ASSERT_TRUE(r.ok());
        z.Add(r, kQuadTruth);
        chi2_sum += r.chi2;
    }
    for (size_t j = 0; j < 3; ++j) {
        EXPECT_NEAR(z.Std(j), 1.0, 4.0 / std::sqrt(2.0 * (kN - 1))) << "coefficient " << j;
        EXPECT_NEAR(z.Mean(j), 0.0, 4.0 / std::sqrt(kN)) << "coefficient " << j;
    }
    EXPECT_NEAR(chi2_sum / kN, 4.0, 4.0 * std::sqrt(8.0 / kN));
}

// The same calibration for the 3-point solution (no chi2 there: it is exact).
TEST(SeedThreePoint, ReportedCovarianceMatchesTheScatterOver500Seeds) {
    constexpr int kN = 500;
    std::mt19937_64 rng(7);
    const Poly truth{-10.0, {2.49, 3e-4, 2e-6}};  // truth written about the seed's T0
    testing::ZScores z(3);
    for (int k = 0; k < kN; ++k) {
        const FitResult r =
            SeedThreePoint(Points(truth, {-10, 30, 60}, {2e-5, 1e-5, 3e-5}, rng), "offset_v");
        ASSERT_TRUE(r.ok());
        z.Add(r, truth);
    }
    for (size_t j = 0; j < 3; ++j) {
        EXPECT_NEAR(z.Std(j), 1.0, 4.0 / std::sqrt(2.0 * (kN - 1))) << "coefficient " << j;
    }
}

TEST(FitWls, UnderstatedErrorsAreReportedAndTheCovarianceScaledByTheBirgeRatio) {
    // GIVEN sems 5x smaller than the real noise, chi2/dof ~ 25 >> 1 + 3 sqrt(2/4) = 3.1.
    std::mt19937_64 rng(3);
    std::vector<FitPoint> pts = Points(kQuadTruth, kTemps, {5e-5}, rng);
    for (FitPoint& p : pts) p.sigma_y = 1e-5;
    const FitResult r = FitPolynomial(pts, "offset_v", Quadratic());
    ASSERT_TRUE(r.ok());
    EXPECT_TRUE(r.scatter_exceeds_errors) << r.chi2_per_dof;
    EXPECT_NE(r.detail.find("scatter exceeds"), std::string::npos) << r.detail;
    // THEN with the degree fixed, c is the fit's own chi2/dof, reported, and the covariance is
    // what the stated errors imply times max(1, c) (the Birge ratio, fit.hpp)
    EXPECT_EQ(r.overdispersion_dof, 4);
    EXPECT_DOUBLE_EQ(r.overdispersion, r.chi2_per_dof);
    EXPECT_DOUBLE_EQ(r.covariance_scale, r.chi2_per_dof);
    EXPECT_NE(r.detail.find("overdispersion c"), std::string::npos) << r.detail;
    const FitResult stated = FitWls(pts, model::PolynomialTerms(2), r.model.t0_c, "offset_v");
    ASSERT_TRUE(stated.ok());
    EXPECT_NEAR(r.model.covariance(0, 0), r.chi2_per_dof * stated.model.covariance(0, 0),
                1e-9 * r.model.covariance(0, 0));
}

TEST(FitWls, GeneralTermListsForTheAnalysis) {
    // y = 1 + 0.5 supply' + 0.01 dT with supply' = supply_v - the nominal: the term registry drives
    // the fit.
    std::vector<FitPoint> pts;
    std::mt19937_64 rng(11);
    std::normal_distribution<double> n01;
    for (int i = 0; i < 20; ++i) {
        FitPoint p;
        p.inputs.temp_c = -10 + 3.5 * i;
        p.inputs.supply_v = 4.9 + 0.01 * ((i * 7) % 20);
        p.sigma_y = 1e-4;
        p.y = 1 + 0.5 * (p.inputs.supply_v - model::kNominalSupplyV) +
              0.01 * (p.inputs.temp_c - 25) + p.sigma_y * n01(rng);
        pts.push_back(p);
    }
    const FitResult r = FitWls(pts, {"1", "dT", "supply"}, 25.0, "offset_v");
    ASSERT_TRUE(r.ok()) << r.detail;
    EXPECT_NEAR(r.model.coeffs[2], 0.5, 4 * std::sqrt(r.model.covariance(2, 2)));
    // a term whose input is missing: refused, not a NaN model
    pts[3].inputs.supply_v = NAN;
    EXPECT_EQ(FitWls(pts, {"1", "dT", "supply"}, 25.0, "offset_v").refusal,
              Refusal::kNonFiniteInput);
    // collinear terms: ill-conditioned
    EXPECT_EQ(FitWls(pts, {"1", "heating"}, 25.0, "offset_v").refusal, Refusal::kNonFiniteInput);
    for (FitPoint& p : pts) {
        p.inputs.heating = 1.0;
        p.inputs.branch_width_c = GYROCAL_SIGN_BRANCH_WIDTH_C;  // as the tracker reports it
    }
    EXPECT_EQ(FitWls(pts, {"1", "heating"}, 25.0, "offset_v").refusal, Refusal::kIllConditioned);
}

}  // namespace
}  // namespace gyrocal::fit
