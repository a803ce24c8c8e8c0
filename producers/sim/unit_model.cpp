#include "producers/sim/unit_model.hpp"

namespace gyrocal::sim {

double UnitTruth::OffsetV(double die_c) const {
    const double dt = die_c - kTruthT0C;
    return offset_coeffs[0] + dt * (offset_coeffs[1] + dt * offset_coeffs[2]);
}

double UnitTruth::SensitivityVPerDps(double die_c) const {
    const double dt = die_c - kTruthT0C;
    return sensitivity_coeffs[0] + dt * (sensitivity_coeffs[1] + dt * sensitivity_coeffs[2]);
}

UnitTruth DrawUnit(const RigConfig& config, int unit_index, const std::string& sensor_id) {
    // The order of draws below is part of the output format: changing it changes every unit.
    Rng rng(config.seed, UnitParamStream(unit_index));
    const SpreadConfig& sp = config.spread;
    UnitTruth u;
    u.sensor_id = sensor_id;
    u.offset_coeffs[0] = config.preset.null_v + sp.null_std_v * rng.Normal();
    u.offset_coeffs[1] =
        rng.Sign() * rng.Uniform(sp.offset_tc_min_v_per_c, sp.offset_tc_max_v_per_c);
    u.offset_coeffs[2] =
        rng.Sign() * rng.Uniform(sp.offset_tc2_min_v_per_c2, sp.offset_tc2_max_v_per_c2);
    const double s0 = config.preset.sensitivity_v_per_dps * (1.0 + sp.sens_std_frac * rng.Normal());
    u.sensitivity_coeffs[0] = s0;
    u.sensitivity_coeffs[1] =
        s0 * rng.Sign() * rng.Uniform(sp.sens_tc_min_per_c, sp.sens_tc_max_per_c);
    u.sensitivity_coeffs[2] =
        s0 * rng.Sign() * rng.Uniform(sp.sens_tc2_min_per_c2, sp.sens_tc2_max_per_c2);
    u.temp_sensor_offset_c = sp.temp_sensor_offset_std_c * rng.Normal();
    u.package_tau_s =
        config.thermal.package_tau_s * (1.0 + sp.package_tau_spread_frac * rng.Normal());
    if (u.package_tau_s < 0.1 * config.thermal.package_tau_s) {
        u.package_tau_s = 0.1 * config.thermal.package_tau_s;  // a 6-sigma draw stays physical
    }
    return u;
}

}  // namespace gyrocal::sim
