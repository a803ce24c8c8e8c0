#pragma once
// Correlated noise with a known spectrum, for tests of estimators on correlated series.
#include <cmath>
#include <cstdint>
#include <random>

namespace gyrocal::numeric::testing {

// AR(1) noise x_k = rho x_{k-1} + sqrt(1 - rho^2) sigma e_k: stationary std sigma, correlation
// rho^|lag|, the variance of an n-sample mean -> sigma^2/n * (1 + rho)/(1 - rho) for large n.
class Ar1 {
public:
    Ar1(double sigma, double rho, uint64_t seed) : sigma_(sigma), rho_(rho), rng_(seed) {
        x_ = sigma_ * n_(rng_);
    }
    double Next() {
        x_ = rho_ * x_ + std::sqrt(1 - rho_ * rho_) * sigma_ * n_(rng_);
        return x_;
    }

private:
    double sigma_, rho_, x_ = 0;
    std::mt19937_64 rng_;
    std::normal_distribution<double> n_{0.0, 1.0};
};

}  // namespace gyrocal::numeric::testing
