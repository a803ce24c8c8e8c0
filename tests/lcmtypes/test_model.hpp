#pragma once
// The test model every model-carrying test builds on: fitted on dT = T - 25 degC over the valid
// range -10..60 degC. Its forms differ (the message model_t, the library's model::Model, the
// store's ModelRow) but share these scalars by name, as processors/model/convert.hpp's
// CopyModelScalars copies them; each test keeps its own fit figures.
#include <cstdint>

namespace gyrocal::testing {

struct TestModelFit {
    double residual_rms = 1e-5;  // [unit of y]
    int32_t n_points = 3;        // [count]
    double condition_number = 12.0;
    const char* method = "wls";
};

template <class M>
void SetTestModelScalars(M& m, const TestModelFit& fit = {}) {
    m.t0_c = 25.0;
    m.temp_min_c = -10.0;
    m.temp_max_c = 60.0;
    m.residual_rms = fit.residual_rms;
    m.n_points = fit.n_points;
    m.condition_number = fit.condition_number;
    m.method = fit.method;
}

}  // namespace gyrocal::testing
