// Statistics of correlated series: the batch-means SEM and the pooled noise level against the
// truth of correlated noise over many seeds.
#include "processors/numeric/series_stats.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "tests/processors/numeric/synthetic_noise.hpp"

namespace gyrocal::numeric {
namespace {

TEST(SeriesStats, BatchMeansSemMatchesTheScatterOfMeansForCorrelatedNoise) {
    // GIVEN M = 200 windows of n = 6000 AR(1) samples (rho = 0.9, sigma = 1)
    const int m = 200, n = 6000, batches = 20;
    const double rho = 0.9;
    std::vector<double> means;
    double sem_sum = 0, naive_sum = 0;
    for (int seed = 0; seed < m; ++seed) {
        testing::Ar1 noise(1.0, rho, 1000 + seed);
        std::vector<double> x(n);
        for (double& v : x) v = noise.Next();
        const MeanStats s = DescribeSeries(x, batches);
        means.push_back(s.mean);
        sem_sum += s.sem;
        naive_sum += s.std / std::sqrt(static_cast<double>(n));
    }
    double mu = 0;
    for (double v : means) mu += v;
    mu /= m;
    double ss = 0;
    for (double v : means) ss += (v - mu) * (v - mu);
    const double empirical = std::sqrt(ss / (m - 1));
    const double reported = sem_sum / m;
    // THEN the average reported SEM matches the empirical scatter of the means. Uncertainty of the
    // ratio: empirical sd over M windows 1/sqrt(2(M-1)) = 5.0%; mean of M batch-means SEMs
    // 1/sqrt(2(B-2))/sqrt(M) = 1.2%; 3 sigma of both is 15.5%; batch-means bias for batches of
    // 300 samples >> 1/(1-rho) = 10 is < 2%: tolerance 0.175.
    EXPECT_NEAR(reported / empirical, 1.0, 0.175);
    // and the white-noise formula would fail it (sqrt((1-rho)/(1+rho)) = 0.23).
    EXPECT_LT(naive_sum / m / empirical, 0.5);
}

TEST(SeriesStats, SemIgnoresALinearDriftInsideTheWindow) {
    // GIVEN white noise sigma = 1 plus a drift of 10 sigma across the window
    const int n = 6000;
    std::mt19937_64 rng(4);
    std::normal_distribution<double> g(0, 1);
    std::vector<double> x(n);
    for (int i = 0; i < n; ++i) x[i] = 10.0 * i / n + g(rng);
    const MeanStats s = DescribeSeries(x, 20);
    // THEN the SEM is that of the noise (1/sqrt(n)) within 3 x 16.7% (batch-means scatter)
    EXPECT_NEAR(s.sem * std::sqrt(static_cast<double>(n)), 1.0, 0.5);
}

TEST(SeriesStats, SmallSeriesFallBackToTheWhiteFormula) {
    const MeanStats s = DescribeSeries({1.0, 2.0, 3.0, 4.0, 5.0}, 20);
    EXPECT_EQ(s.batches, 0);
    EXPECT_DOUBLE_EQ(s.mean, 3.0);
    EXPECT_DOUBLE_EQ(s.std, std::sqrt(2.5));
    EXPECT_DOUBLE_EQ(s.sem, std::sqrt(2.5 / 5));
    EXPECT_TRUE(std::isnan(DescribeSeries({}, 20).mean));
}

TEST(SeriesStats, PooledNoiseLevelFindsTheSpectralLevelOfShortCorrelatedWindows) {
    // GIVEN 300 pairs of 200-sample AR(1) windows (a rotation's two 2 s rest windows) with
    // rho = 0 and 0.8: the spectral level per sample var * tau_int is sigma^2 (1 + rho)/(1 - rho).
    for (double rho : {0.0, 0.8}) {
        SCOPED_TRACE(rho);
        double sum = 0;
        const int m = 300;
        for (int k = 0; k < m; ++k) {
            testing::Ar1 noise(1.0, rho, 500 + k);
            std::vector<double> a(200), b(200);
            for (double& v : a) v = noise.Next();
            for (int i = 0; i < 300; ++i) noise.Next();  // the move between them
            for (double& v : b) v = noise.Next();
            const NoiseLevel lvl = PooledNoiseLevel({a, b});
            EXPECT_EQ(lvl.n, 400);
            EXPECT_GE(lvl.tau_int, 1.0);
            sum += lvl.var * lvl.tau_int;
        }
        // THEN the average over windows is close to the truth. Each estimate scatters ~30 % at
        // rho = 0.8, so the mean of 300 has ~1.7 %: under-estimation (a too-small reported
        // uncertainty) is allowed only 4 of those, 7 %. Over-estimation is allowed 15 %: the
        // initial sequence also sums the first noise-only pairs while they happen to be
        // positive, each worth ~2/sqrt(400) = 10 % of gamma_0 at most once on average (the
        // monotone cap stops the rest) -- conservative by design.
        const double ratio = sum / m / ((1 + rho) / (1 - rho));
        EXPECT_GT(ratio, 0.93);
        EXPECT_LT(ratio, 1.15);
    }
}

}  // namespace
}  // namespace gyrocal::numeric
