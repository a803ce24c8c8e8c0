#include "producers/sim/noise.hpp"

#include <cmath>

namespace gyrocal::sim {

double GaussMarkovAvar(double q, double t_corr_s, double tau_s) {
    const double x = tau_s / t_corr_s;
    return q * q * (2.0 * x - 3.0 + 4.0 * std::exp(-x) - std::exp(-2.0 * x)) / (x * x);
}

namespace {

constexpr std::array<double, 4> kTaus = {1.0, 10.0, 100.0, 1000.0};

// Flat level of the bank with q = 1: the mean of its Allan deviation over 10..500 s.
double UnitBankLevel() {
    double sum = 0.0;
    int n = 0;
    for (double tau = 10.0; tau <= 500.0; tau *= 1.5) {
        double avar = 0.0;
        for (double t : kTaus) avar += GaussMarkovAvar(1.0, t, tau);
        sum += std::sqrt(avar);
        ++n;
    }
    return sum / n;
}

}  // namespace

double BiasInstabilityComponentSigma(double bias_instability_dps) {
    static const double level = UnitBankLevel();
    return bias_instability_dps / level;
}

double TheoreticalAdev(const NoiseConfig& c, double tau_s) {
    double avar = c.noise_density_dps_rthz * c.noise_density_dps_rthz / tau_s;
    const double q = BiasInstabilityComponentSigma(c.bias_instability_dps);
    for (double t : kTaus) avar += GaussMarkovAvar(q, t, tau_s);
    avar += c.rate_random_walk_dps_rts * c.rate_random_walk_dps_rts * tau_s / 3.0;
    return std::sqrt(avar);
}

NoiseModel::NoiseModel(const NoiseConfig& c, double sample_rate_hz, Rng& rng) {
    const double dt = 1.0 / sample_rate_hz;
    white_sigma_dps_ = c.noise_density_dps_rthz * std::sqrt(sample_rate_hz);
    rrw_step_dps_ = c.rate_random_walk_dps_rts * std::sqrt(dt);
    const double q = BiasInstabilityComponentSigma(c.bias_instability_dps);
    for (size_t k = 0; k < kGmTauS.size(); ++k) {
        gm_phi_[k] = std::exp(-dt / kGmTauS[k]);
        gm_drive_[k] = q * std::sqrt(1.0 - gm_phi_[k] * gm_phi_[k]);
        gm_state_[k] = q * rng.Normal();  // stationary start
    }
}

double NoiseModel::Next(Rng& rng) {
    double bias = 0.0;
    const double white = white_sigma_dps_ * rng.Normal();
    for (size_t k = 0; k < gm_state_.size(); ++k) {
        gm_state_[k] = gm_phi_[k] * gm_state_[k] + gm_drive_[k] * rng.Normal();
        bias += gm_state_[k];
    }
    rrw_state_dps_ += rrw_step_dps_ * rng.Normal();
    return white + bias + rrw_state_dps_;
}

double SlowNoiseBinVariance(const NoiseConfig& c, double bin_s, double span_s) {
    const double q = BiasInstabilityComponentSigma(c.bias_instability_dps);
    double var = 0.0;
    for (double t : kTaus) {
        const double x = bin_s / t;
        var += q * q * 2.0 * (x - 1.0 + std::exp(-x)) / (x * x);
    }
    return var + c.rate_random_walk_dps_rts * c.rate_random_walk_dps_rts * span_s / 2.0;
}

}  // namespace gyrocal::sim
