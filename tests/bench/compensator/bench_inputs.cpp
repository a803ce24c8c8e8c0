#include "tests/bench/compensator/bench_inputs.hpp"

#include <cmath>
#include <random>

#include "processors/model/inputs.hpp"

namespace gyrocal::bench {

std::optional<ModelKind> ParseModelKind(const std::string& text) {
    if (text == "quadratic") return ModelKind::kQuadratic;
    if (text == "extended") return ModelKind::kExtended;
    return std::nullopt;
}

const char* ToString(ModelKind kind) {
    return kind == ModelKind::kQuadratic ? "quadratic" : "extended";
}

namespace {

model::Model MakeModel(const char* quantity, std::vector<std::string> names,
                       const std::vector<double>& coeffs) {
    model::Model m;
    m.quantity = quantity;
    m.term_names = std::move(names);
    m.coeffs =
        Eigen::Map<const Eigen::VectorXd>(coeffs.data(), static_cast<Eigen::Index>(coeffs.size()));
    // 0.1 % standard uncertainty per coefficient, uncorrelated: the values do not change the cost
    // (the covariance product is dense either way).
    m.covariance = (1e-3 * m.coeffs.cwiseAbs()).cwiseAbs2().asDiagonal();
    m.t0_c = 25.0;
    m.temp_min_c = -40.0;
    m.temp_max_c = 85.0;
    m.residual_rms = 1e-5;
    m.n_points = 9;
    m.method = "wls";
    return m;
}

}  // namespace

model::CoeffSet BenchSet(ModelKind kind, const std::string& sensor_id) {
    model::CoeffSet s;
    s.utime = 1;
    s.coeff_set_id = 1;
    s.sensor_id = sensor_id;
    s.run_id = "bench";
    s.source = "fitter";
    if (kind == ModelKind::kQuadratic) {
        s.offset = MakeModel(model::kOffsetQuantity, {"1", "dT", "dT^2"}, {2.5, 4e-4, 3e-6});
    } else {
        // dT/dt [V/(degC/s)], branch [V], supply [V/V], warm-up [V]
        s.offset = MakeModel(model::kOffsetQuantity,
                             {"1", "dT", "dT^2", "dT^3", model::RateTerm(20.0),
                              model::BranchTerm(2.0), "supply", model::WarmupTerm(400.0)},
                             {2.5, 4e-4, 3e-6, -2e-8, 0.05, 5e-4, 0.02, 4e-3});
    }
    std::vector<std::string> sens_terms = {"1", "dT", "dT^2"};
    std::vector<double> sens_coeffs = {0.006, 6e-7, -1.2e-8};
    if (kind == ModelKind::kExtended) {
        sens_terms.push_back("direction");
        sens_coeffs.push_back(3e-5);  // +-0.5 % scale-factor asymmetry
    }
    s.sensitivity = MakeModel(model::kSensitivityQuantity, sens_terms, sens_coeffs);
    s.plateau_ids = {1, 2, 3, 4, 5, 6, 7, 8, 9};
    s.rotation_ids = {1, 2, 3, 4, 5, 6, 7, 8, 9};
    return s;
}

namespace {

// In [-1, 1]: 0 at phase 0, rising to 1 at a quarter period, -1 at three quarters.
double Triangle(double phase) {
    const double p = phase - std::floor(phase);
    if (p < 0.25) return 4.0 * p;
    if (p < 0.75) return 2.0 - 4.0 * p;
    return 4.0 * p - 4.0;
}

}  // namespace

std::vector<RawSample> SyntheticStream(int unit, double rate_hz, int64_t n) {
    const model::CoeffSet truth = BenchSet(ModelKind::kExtended, "B01");
    const model::Evaluator off(truth.offset), sens(truth.sensitivity);
    model::InputTracker tracker(model::TrackerConfigFor({&truth.offset, &truth.sensitivity}));
    std::mt19937_64 rng(1000 + static_cast<uint64_t>(unit));
    std::normal_distribution<double> temp_noise(0.0, 0.02), gyro_noise(0.0, 2e-3),
        supply_noise(0.0, 5e-4);
    std::vector<RawSample> out(static_cast<size_t>(n));
    for (int64_t k = 0; k < n; ++k) {
        const double t_s = static_cast<double>(k) / rate_hz;
        RawSample& s = out[static_cast<size_t>(k)];
        s.temp_c = 25.0 + 10.0 * Triangle(t_s / kTempPeriodS) + temp_noise(rng);
        s.supply_v = 5.0 + 0.005 * std::sin(2 * M_PI * t_s / 60.0 + unit) + supply_noise(rng);
        const double rate_dps = 30.0 * std::sin(2 * M_PI * t_s / 8.0 + 0.7 * unit);
        model::ModelInputs in =
            tracker.Update(static_cast<int64_t>(std::llround(t_s * 1e6)), s.temp_c, s.supply_v);
        in.direction = rate_dps >= 0.0 ? 1.0 : -1.0;
        const model::RangePolicy p = model::RangePolicy::kExtrapolate;
        s.gyro_v = off.Value(in, p) + sens.Value(in, p) * rate_dps + gyro_noise(rng);
    }
    return out;
}

}  // namespace gyrocal::bench
