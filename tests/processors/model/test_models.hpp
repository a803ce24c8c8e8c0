#pragma once
// Small hand-made models shared by the model tests (and the store's, through the interface
// library gyrocal_test_models), and the checks they share: a model or a set equal in every field
// after a conversion and back, a bad model refused with a message naming the problem.
#include <gtest/gtest.h>

#include <string>
#include <tuple>

#include "processors/model/convert.hpp"
#include "processors/model/model.hpp"
#include "tests/lcmtypes/test_model.hpp"

namespace gyrocal::model::testing {

inline Model Quadratic(const char* quantity = kOffsetQuantity) {
    Model m;
    m.quantity = quantity;
    m.term_names = {"1", "dT", "dT^2"};
    m.coeffs = Eigen::Vector3d(2.5, 4e-4, 3e-6);
    m.covariance.resize(3, 3);
    m.covariance << 4e-10, 1e-12, -2e-13, 1e-12, 9e-13, 1e-15, -2e-13, 1e-15, 4e-16;
    gyrocal::testing::SetTestModelScalars(
        m, {.residual_rms = 1.5e-5, .n_points = 5, .condition_number = 3.2});
    return m;
}

// Every field, exactly (a model or a set that went through a conversion and back).
inline void ExpectSameModel(const Model& a, const Model& b) {
    EXPECT_EQ(a.quantity, b.quantity);
    EXPECT_EQ(a.term_names, b.term_names);
    EXPECT_EQ(a.coeffs, b.coeffs);
    EXPECT_EQ(a.covariance, b.covariance);
    EXPECT_EQ(a.t0_c, b.t0_c);
    EXPECT_EQ(a.temp_min_c, b.temp_min_c);
    EXPECT_EQ(a.temp_max_c, b.temp_max_c);
    EXPECT_EQ(a.residual_rms, b.residual_rms);
    EXPECT_EQ(a.n_points, b.n_points);
    EXPECT_EQ(a.condition_number, b.condition_number);
    EXPECT_EQ(a.method, b.method);
}

inline void ExpectSameSet(const CoeffSet& a, const CoeffSet& b) {
    auto identity = [](const CoeffSet& s) {
        return std::tie(s.utime, s.sensor_id, s.run_id, s.coeff_set_id, s.source, s.plateau_ids,
                        s.rotation_ids);
    };
    EXPECT_EQ(identity(a), identity(b));
    ExpectSameModel(a.offset, b.offset);
    ExpectSameModel(a.sensitivity, b.sensitivity);
}

// Expects `use()` to throw a ModelError whose message names `words`.
template <class Use>
void ExpectRefused(Use&& use, const std::string& words) {
    try {
        use();
        ADD_FAILURE() << "accepted, expected: " << words;
    } catch (const ModelError& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

}  // namespace gyrocal::model::testing
