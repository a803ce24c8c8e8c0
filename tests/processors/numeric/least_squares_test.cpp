// The one least-squares solver (numeric/least_squares.hpp) and its callers: the fitter's
// weighted fit on plateau points (FitWls) and the analysis' fit on still bins (analysis::FitLs,
// its blocked cross-validation and projected correlation).
//
// (1) The solver against the truth: noise-free data are reproduced to rounding, and the
//     covariance equals the normal equations' (X'WX)^-1 on a well-conditioned system.
// (2) The callers give the numbers they gave before they shared the solver, on one fixed input
//     (below): the reference figures were printed by the code as it stood before the move (each
//     caller with its own QR), so any change of the arithmetic beyond round-off shows here. The
//     tolerance: relative 1e-12, ~5000 ulp; the QR of a 60 x 4 system scaled to unit columns
//     (condition ~10) differs between two orders of the same operations by a few ulp per
//     element, far below it, while any change of method (another weighting, a missing scale, a
//     different covariance) changes the figures at 1e-3 or more.
#include "processors/numeric/least_squares.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "processors/analysis/regress.hpp"
#include "processors/fit/fit.hpp"
#include "tests/processors/numeric/synthetic_noise.hpp"

namespace gyrocal {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

using numeric::testing::Lcg;

// The fixed input: 60 bins, temperature swept -30 .. 75 degC, columns 1, dT, dT^2 and a slow
// exponential (a warm-up-like regressor), y with correlated noise (AR(1) 0.6) of ~1e-4.
struct Fixed {
    MatrixXd x;
    VectorXd y;
    std::vector<int> segment;
};
Fixed MakeFixed() {
    Fixed f;
    const Index n = 60;
    f.x.resize(n, 4);
    f.y.resize(n);
    Lcg rng{12345};
    double ar = 0.0;
    for (Index i = 0; i < n; ++i) {
        const double t = -30.0 + 105.0 * static_cast<double>(i) / (n - 1) + 3.0 * std::sin(0.7 * i);
        const double dt = t - 25.0;
        f.x(i, 0) = 1.0;
        f.x(i, 1) = dt;
        f.x(i, 2) = dt * dt;
        f.x(i, 3) = std::exp(-static_cast<double>(i) / 12.0);
        ar = 0.6 * ar + 2e-4 * rng();
        f.y[i] = 2.5 + 6e-4 * dt + 3e-6 * dt * dt + 2e-3 * f.x(i, 3) + ar;
        f.segment.push_back(i < 35 ? 0 : 1);
    }
    return f;
}

void ExpectRel(double got, double want, const char* what) {
    EXPECT_NEAR(got, want, 1e-12 * std::fabs(want) + 1e-300) << what;
}

TEST(LeastSquares, NoiseFreeDataAreReproducedAndTheCovarianceIsTheNormalEquations) {
    const Fixed f = MakeFixed();
    const VectorXd truth = (VectorXd(4) << 2.5, 6e-4, 3e-6, 2e-3).finished();
    const VectorXd y = f.x * truth;
    VectorXd sigma(f.x.rows());
    for (Index i = 0; i < sigma.size(); ++i) sigma[i] = 1e-5 * (1.0 + 0.5 * (i % 3));
    const numeric::LeastSquares ls = numeric::SolveLeastSquares(f.x, y, &sigma);
    ASSERT_TRUE(ls.ok) << ls.why;
    EXPECT_EQ(ls.rank, 4);
    // 1e-11 relative: a QR of a condition-~100 scaled system loses a few digits of 16.
    for (Index j = 0; j < 4; ++j) EXPECT_NEAR(ls.coeffs[j], truth[j], 1e-11 * std::fabs(truth[j]));
    const MatrixXd xw = sigma.cwiseInverse().asDiagonal() * f.x;
    const MatrixXd normal = (xw.transpose() * xw).ldlt().solve(MatrixXd::Identity(4, 4));
    for (Index i = 0; i < 4; ++i)
        for (Index j = 0; j < 4; ++j)
            EXPECT_NEAR(ls.xtwx_inv(i, j), normal(i, j),
                        1e-8 * std::sqrt(normal(i, i) * normal(j, j)));
    // Whitened residuals of noise-free data are rounding: 2.5 V x 2.2e-16 / 1e-5 V ~ 5e-11 per
    // row at most a few times that; over 60 rows rss < 60 x (1.3e-10)^2 = 1e-18.
    EXPECT_LT(ls.rss, 1e-18);
}

TEST(LeastSquares, RefusesARankDeficientDesignAndSaysWhichColumn) {
    Fixed f = MakeFixed();
    f.x.col(3) = 2.0 * f.x.col(1);
    const numeric::LeastSquares ls = numeric::SolveLeastSquares(f.x, f.y);
    EXPECT_FALSE(ls.ok);
    EXPECT_NE(ls.why.find("rank"), std::string::npos) << ls.why;
    f.x.col(2).setZero();
    const numeric::LeastSquares z = numeric::SolveLeastSquares(f.x, f.y);
    EXPECT_FALSE(z.ok);
    EXPECT_NE(z.why.find("column 2"), std::string::npos) << z.why;
}

// Reference figures printed by analysis::FitLs / BlockedCvMse / ProjectedCorrelation and
// fit::FitWls before they shared the solver (see the header comment).
TEST(LeastSquares, AnalysisCallerGivesTheNumbersItGaveBefore) {
    const Fixed f = MakeFixed();
    const analysis::LsFit r = analysis::FitLs(f.x, f.y, f.segment, 5);
    ASSERT_TRUE(r.ok) << r.why;
    const double coeffs[] = {2.499982126733459, 0.00059814409946185737, 3.0372145930023461e-06,
                             0.0018032678951888672};
    for (Index j = 0; j < 4; ++j) ExpectRel(r.coeffs[j], coeffs[j], "analysis coefficient");
    ExpectRel(r.covariance(0, 0), 4.7024077840335508e-10, "analysis covariance 0,0");
    ExpectRel(r.covariance(1, 1), 1.176394628091193e-12, "analysis covariance 1,1");
    ExpectRel(r.covariance(3, 3), 2.2765567649285778e-08, "analysis covariance 3,3");
    ExpectRel(r.covariance(1, 3), 1.5118586119278724e-10, "analysis covariance 1,3");
    ExpectRel(r.rss, 2.6408122638527624e-07, "analysis rss");
    ExpectRel(r.lag1_autocorr, 0.46697072233738679, "analysis lag-1 autocorrelation");
    ExpectRel(analysis::BlockedCvMse(f.x, f.y, 6, 2), 8.0156224724467421e-09, "blocked CV MSE");
    ExpectRel(analysis::ProjectedCorrelation(f.x.leftCols(2), f.x.col(2), f.x.col(3)),
              0.89919589262950761, "projected correlation");
}

TEST(LeastSquares, FitterCallerGivesTheNumbersItGaveBefore) {
    const Fixed f = MakeFixed();
    std::vector<fit::FitPoint> pts;
    for (Index i = 0; i < f.x.rows(); i += 6) {
        fit::FitPoint p;
        p.inputs.temp_c = f.x(i, 1) + 25.0;
        p.y = f.y[i];
        p.sigma_y = 3e-5 * (1.0 + 0.25 * static_cast<double>(i % 4));
        p.id = i;
        pts.push_back(p);
    }
    const fit::FitResult r = fit::FitWls(pts, model::PolynomialTerms(2), 25.0, "offset_v");
    ASSERT_TRUE(r.ok()) << r.detail;
    const model::Model& m = r.model;
    const double coeffs[] = {2.5000658210636368, 0.00058698077549315588, 3.3421009994869237e-06};
    for (Index j = 0; j < 3; ++j) ExpectRel(m.coeffs[j], coeffs[j], "wls coefficient");
    ExpectRel(m.covariance(0, 0), 2.7013790272849921e-10, "wls covariance 0,0");
    ExpectRel(m.covariance(1, 1), 1.7719257929065584e-13, "wls covariance 1,1");
    ExpectRel(m.covariance(2, 2), 1.7099808773728802e-16, "wls covariance 2,2");
    ExpectRel(m.covariance(0, 2), -1.5219828077676996e-13, "wls covariance 0,2");
    ExpectRel(r.chi2, 77.554794848325457, "wls chi2");
    ExpectRel(m.condition_number, 3.079198537884841, "wls condition number");
    ExpectRel(m.residual_rms, 9.8308293591086848e-05, "wls residual rms");
}

}  // namespace
}  // namespace gyrocal
