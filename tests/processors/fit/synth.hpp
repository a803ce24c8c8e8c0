#pragma once
// Synthetic calibration points with known truth: y = truth(T) + N(0, sigma_i), T exact.
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "processors/fit/fit.hpp"

namespace gyrocal::fit::testing {

// Truth as coefficients of 1, dT, dT^2, dT^3 about t0_c.
struct Poly {
    double t0_c = 25.0;
    std::vector<double> c;
    double operator()(double temp_c) const {
        double y = 0, p = 1;
        for (double ci : c) {
            y += ci * p;
            p *= temp_c - t0_c;
        }
        return y;
    }
};

inline std::vector<FitPoint> Points(const Poly& truth, const std::vector<double>& temps_c,
                                    const std::vector<double>& sigmas, std::mt19937_64& rng) {
    std::vector<FitPoint> pts;
    std::normal_distribution<double> n01(0.0, 1.0);
    for (size_t i = 0; i < temps_c.size(); ++i) {
        FitPoint p;
        p.inputs.temp_c = temps_c[i];
        p.sigma_y = sigmas[i % sigmas.size()];
        p.y = truth(temps_c[i]) + p.sigma_y * n01(rng);
        p.id = static_cast<int64_t>(1000 + i);
        pts.push_back(p);
    }
    return pts;
}

// The normalised errors z_j = (est_j - true_j) / sqrt(C_jj) of a fit's coefficients, collected
// over many noise draws: N(0, 1) when the reported covariance is right (the calibration tests
// compare their sample mean and standard deviation with that).
class ZScores {
public:
    explicit ZScores(size_t n_coeffs) : z_(n_coeffs) {}
    void Add(const FitResult& r, const Poly& truth) {
        for (size_t j = 0; j < z_.size(); ++j) {
            const auto i = static_cast<Eigen::Index>(j);
            z_[j].push_back((r.model.coeffs[i] - truth.c[j]) / std::sqrt(r.model.covariance(i, i)));
        }
    }
    double Mean(size_t j) const {
        double mean = 0;
        for (double v : z_[j]) mean += v / static_cast<double>(z_[j].size());
        return mean;
    }
    // Sample standard deviation (n - 1 in the denominator).
    double Std(size_t j) const {
        const double mean = Mean(j), n = static_cast<double>(z_[j].size());
        double var = 0;
        for (double v : z_[j]) var += (v - mean) * (v - mean) / (n - 1);
        return std::sqrt(var);
    }

private:
    std::vector<std::vector<double>> z_;  // [coefficient][draw]
};

}  // namespace gyrocal::fit::testing
