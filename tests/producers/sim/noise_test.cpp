// Statistical tests of the noise model (Allan deviation).
// Tolerances: the overlapping Allan deviation at cluster size m from N samples has a relative
// standard deviation below that of the non-overlapping estimator, 1/sqrt(2 (N/m - 1)); tests
// allow 4 of those (false-failure chance ~1e-4 per check), plus any stated model bias.
#include "producers/sim/noise.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "producers/sim/rig.hpp"
#include "tests/producers/sim/sim_test_support.hpp"

namespace gyrocal::sim {
namespace {

using testing::AllanDeviation;

double RelSigma(size_t n, size_t m) {
    return 1.0 / std::sqrt(2.0 * (static_cast<double>(n) / m - 1.0));
}

// A still, isothermal record of one unit, converted back to deg/s with the unit's truth.
std::vector<double> StillRateRecord(const RigConfig& c, double seconds) {
    Rig rig(c);
    testing::RecordingSink sink;
    rig.RunUntil(c.start_utime + static_cast<int64_t>(seconds * 1e6), sink);
    std::vector<double> rate;
    rate.reserve(sink.data.gyro.size());
    for (size_t i = 0; i < sink.data.gyro.size(); ++i) {
        const GyroTruth& t = sink.data.truth[i];
        rate.push_back((sink.data.gyro[i].gyro_v - t.offset_v) / t.sensitivity_v_per_dps);
    }
    return rate;
}

TEST(SimNoise, WhiteNoiseHasSlopeMinusHalfAndConfiguredDensity) {
    // GIVEN a still unit at constant temperature, white noise only, 16-bit ADC and 40 Hz LPF on
    RigConfig c = testing::QuietConfig();
    c.adc.bits = 16;
    c.noise.noise_density_dps_rthz = 0.05;
    const double dt = 1.0 / c.sample_rate_hz;
    // WHEN one simulated hour is recorded
    const std::vector<double> y = StillRateRecord(c, 3600.0);
    const size_t n = y.size();
    // THEN the Allan deviation falls as tau^-1/2 between 0.1 s and 10 s
    const double a01 = AllanDeviation(y, dt, 10), a1 = AllanDeviation(y, dt, 100),
                 a10 = AllanDeviation(y, dt, 1000);
    const double slope = std::log10(a10 / a01) / 2.0;
    // slope std: sqrt(rel(0.1)^2 + rel(10)^2) / ln(100); 4 sigma, plus 0.01 for the LPF's
    // (~1 % at tau = 0.1 s) reduction of the short-tau deviation.
    const double slope_tol =
        4.0 * std::hypot(RelSigma(n, 10), RelSigma(n, 1000)) / std::log(100.0) + 0.01;
    std::printf(
        "white: adev(0.1 s) %.5f, adev(1 s) %.5f, adev(10 s) %.5f deg/s; slope %.4f +- %.4f; "
        "density %.5f (configured 0.05) +- %.2f %%\n",
        a01, a1, a10, slope, slope_tol, a1, 400.0 * RelSigma(n, 100));
    EXPECT_NEAR(slope, -0.5, slope_tol);
    // and the density read at tau = 1 s matches the configured one (quantization adds
    // LSB/sqrt(12) per sample = 0.0037 deg/s against 0.5 deg/s white: negligible)
    EXPECT_NEAR(a1 / 0.05, 1.0, 4.0 * RelSigma(n, 100));
}

TEST(SimNoise, BiasInstabilityIsTheFlatPart) {
    // GIVEN the noise generator alone, bias instability only, sampled at 1 Hz for 4e6 s
    NoiseConfig nc;
    nc.noise_density_dps_rthz = 0.0;
    nc.rate_random_walk_dps_rts = 0.0;
    nc.bias_instability_dps = 0.008;
    Rng rng(5, 77);
    NoiseModel model(nc, 1.0, rng);
    std::vector<double> y(4'000'000);
    for (double& v : y) v = model.Next(rng);
    // THEN its Allan deviation is flat at the configured level from 5 s to 1000 s: the bank's
    // theoretical ripple is +-5 % (see noise.hpp); estimator 4 sigma on top. The Gauss-Markov
    // components with T = 1000 s have few independent stretches, so the effective count is
    // N/max(m, 2T) rather than N/m.
    for (size_t m : {5, 20, 100, 300, 1000}) {
        const double measured = AllanDeviation(y, 1.0, m);
        std::printf("bias instability: adev(%zu s) = %.5f deg/s (configured level 0.008)\n", m,
                    measured);
        const double tol = 0.05 + 4.0 * RelSigma(y.size(), std::max<size_t>(m, 2000));
        EXPECT_NEAR(measured / 0.008, 1.0, tol) << "tau " << m << " s";
        EXPECT_NEAR(measured / TheoreticalAdev(nc, m), 1.0,
                    4.0 * RelSigma(y.size(), std::max<size_t>(m, 2000)))
            << "tau " << m << " s";
    }
    // and it falls at short tau (below the 1 s component) and long tau (past 1000 s).
    EXPECT_LT(TheoreticalAdev(nc, 0.05), 0.5 * 0.008);
    EXPECT_LT(TheoreticalAdev(nc, 1e5), 0.5 * 0.008);
}

TEST(SimNoise, RateRandomWalkRisesAsSqrtTau) {
    NoiseConfig nc;
    nc.noise_density_dps_rthz = 0.0;
    nc.bias_instability_dps = 0.0;
    nc.rate_random_walk_dps_rts = 1e-3;
    Rng rng(9, 78);
    NoiseModel model(nc, 1.0, rng);
    std::vector<double> y(2'000'000);
    for (double& v : y) v = model.Next(rng);
    for (size_t m : {100, 1000}) {
        const double expected = 1e-3 * std::sqrt(m / 3.0);
        // A random walk's Allan variance estimate converges more slowly: allow 3x the white-case
        // relative sigma at 4 sigma.
        EXPECT_NEAR(AllanDeviation(y, 1.0, m) / expected, 1.0, 12.0 * RelSigma(y.size(), m))
            << "tau " << m;
    }
}

TEST(SimNoise, SlowNoiseBinVarianceMatchesTheRecords) {
    // GIVEN the default slow noise alone (bias instability 0.008 deg/s, rate random walk 5e-5)
    NoiseConfig nc;
    nc.noise_density_dps_rthz = 0.0;
    const double fs = 10.0, bin_s = 10.0, span_s = 3600.0;
    const int records = 60;
    // WHEN 60 one-hour records are cut into 10 s bins
    double sum_sq = 0.0;
    int bins = 0;
    for (int r = 0; r < records; ++r) {
        Rng rng(1000 + r, 79);
        NoiseModel model(nc, fs, rng);
        const int per_bin = static_cast<int>(bin_s * fs);
        for (int b = 0; b < static_cast<int>(span_s / bin_s); ++b) {
            double sum = 0.0;
            for (int k = 0; k < per_bin; ++k) sum += model.Next(rng);
            sum_sq += (sum / per_bin) * (sum / per_bin);
            ++bins;
        }
    }
    const double measured = sum_sq / bins, theory = SlowNoiseBinVariance(nc, bin_s, span_s);
    // THEN the mean square of the bin means is the stated variance. Tolerance: the 1000 s
    // component (35 % of it) has ~span/2T = 1.8 independent values per record, relative sd 0.75
    // per record; the 100 s one (34 %) 0.24; over 60 records that is sqrt((0.35*0.75)^2 +
    // (0.34*0.24)^2)/sqrt(60) = 3.5 %; 4 sigma: 14 %.
    std::printf("slow noise in 10 s bins: measured %.3g (deg/s)^2, theory %.3g\n", measured,
                theory);
    EXPECT_NEAR(measured / theory, 1.0, 0.14);
}

TEST(SimNoise, TheoryMatchesComponentsAlone) {
    NoiseConfig nc;
    nc.noise_density_dps_rthz = 0.05;
    nc.bias_instability_dps = 0.0;
    nc.rate_random_walk_dps_rts = 0.0;
    EXPECT_NEAR(TheoreticalAdev(nc, 4.0), 0.025, 1e-12);
    // Gauss-Markov limits: white-like 2 q^2 T / tau for tau >> T, (2/3) q^2 tau / T for tau << T
    EXPECT_NEAR(GaussMarkovAvar(1.0, 1.0, 1e4) / (2.0 / 1e4), 1.0, 1e-3);
    EXPECT_NEAR(GaussMarkovAvar(1.0, 1e4, 1.0) / (2.0 / 3.0 * 1e-4), 1.0, 1e-3);
}

}  // namespace
}  // namespace gyrocal::sim
