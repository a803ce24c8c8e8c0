#pragma once
// Synthetic calibration points with known truth: y = truth(T) + N(0, sigma_i), T exact.
#include <functional>
#include <random>
#include <vector>

#include "fit/fit.hpp"

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

}  // namespace gyrocal::fit::testing
