#pragma once
// Small hand-made models shared by the model tests.
#include "model/model.hpp"

namespace gyrocal::model::testing {

inline Model Quadratic(const char* quantity = kOffsetQuantity) {
    Model m;
    m.quantity = quantity;
    m.term_names = {"1", "dT", "dT^2"};
    m.coeffs = Eigen::Vector3d(2.5, 4e-4, 3e-6);
    m.covariance.resize(3, 3);
    m.covariance << 4e-10, 1e-12, -2e-13, 1e-12, 9e-13, 1e-15, -2e-13, 1e-15, 4e-16;
    m.t0_c = 25.0;
    m.temp_min_c = -10.0;
    m.temp_max_c = 60.0;
    m.residual_rms = 1.5e-5;
    m.n_points = 5;
    m.condition_number = 3.2;
    m.method = "wls";
    return m;
}

}  // namespace gyrocal::model::testing
