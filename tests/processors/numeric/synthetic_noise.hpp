#pragma once
// Noise for tests of the numerics and their callers: AR(1) noise of a known spectrum (estimators
// on correlated series) and a deterministic uniform generator that gives the same numbers on every
// platform (fixed inputs whose results are compared with figures printed once).
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

// Uniform noise in [-0.5, 0.5): a 64-bit LCG (Knuth's MMIX constants), the same on every platform
// (std:: distributions are not specified bit for bit).
struct Lcg {
    uint64_t s;
    double operator()() {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(s >> 11) / 9007199254740992.0 - 0.5;
    }
};

}  // namespace gyrocal::numeric::testing
