#pragma once
// Rate noise of one gyro unit, in deg/s, one value per sample:
//   white rate noise   : i.i.d. N(0, rho^2 * fs)          -> sigma_A(tau) = rho / sqrt(tau)
//   bias instability   : sum of 4 first-order Gauss-Markov processes with correlation times
//                        1, 10, 100, 1000 s and one common sigma q; decade spacing makes their
//                        summed Allan deviation flat within about +-3 % from ~5 s to ~1000 s,
//                        and q is scaled so that this flat level equals bias_instability_dps.
//   rate random walk   : b += K * sqrt(dt) * N(0,1)        -> sigma_A(tau) = K * sqrt(tau / 3)
// Gauss-Markov states start from their stationary distribution (no start-up transient); the
// random walk starts at 0. Each Next() draws exactly 6 normal deviates whatever the settings, so
// a unit's stream of numbers never depends on which components are switched on.
#include <array>

#include "producers/sim/config.hpp"
#include "producers/sim/rng.hpp"

namespace gyrocal::sim {

class NoiseModel {
public:
    NoiseModel(const NoiseConfig& config, double sample_rate_hz, Rng& rng);
    // Noise of the next sample [deg/s]: white + bias instability + rate random walk.
    double Next(Rng& rng);

private:
    static constexpr std::array<double, 4> kGmTauS = {1.0, 10.0, 100.0, 1000.0};
    double white_sigma_dps_;
    double rrw_step_dps_;
    std::array<double, 4> gm_phi_{};
    std::array<double, 4> gm_drive_{};
    std::array<double, 4> gm_state_{};
    double rrw_state_dps_ = 0.0;
};

// Allan variance [(deg/s)^2] of a first-order Gauss-Markov process of sigma q and correlation
// time T at averaging time tau: q^2 (T/tau)^2 (2 tau/T - 3 + 4 e^(-tau/T) - e^(-2 tau/T)).
double GaussMarkovAvar(double q, double t_corr_s, double tau_s);
// sigma q of each bias-instability component so that the flat level is `bias_instability_dps`.
double BiasInstabilityComponentSigma(double bias_instability_dps);
// The Allan deviation [deg/s] that the configured model has in theory at averaging time tau
// (sampling, low-pass filter and quantization ignored: valid for tau >> 1/fs).
double TheoreticalAdev(const NoiseConfig& config, double tau_s);
// Variance [(deg/s)^2] of bin_s-long means of the SLOW noise (bias instability and rate random
// walk; not the white part), about zero, averaged over a record of span_s: what a perfect model
// still leaves in bin means beyond the white scatter, and what scatter inside short plateau
// windows does not show. A Gauss-Markov process of sigma q and time T averaged over b has
// variance q^2 * 2 (T/b)^2 (b/T - 1 + exp(-b/T)); the random walk's K^2 t averages to
// K^2 span / 2.
double SlowNoiseBinVariance(const NoiseConfig& config, double bin_s, double span_s);

}  // namespace gyrocal::sim
