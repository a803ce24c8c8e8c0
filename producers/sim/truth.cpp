#include "producers/sim/truth.hpp"

namespace gyrocal::sim {

// The configuration sections written whole, every member under its own name (found by
// nlohmann-json's ADL lookup in this namespace).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(NoiseConfig, noise_density_dps_rthz, bias_instability_dps,
                                   rate_random_walk_dps_rts, lpf_hz, temp_noise_v)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ThermalConfig, start_temp_c, ramp_c_per_min, air_tau_s,
                                   air_noise_c, air_noise_tau_s, package_tau_s, sensor_tau_s,
                                   setpoint_tolerance_c, min_setpoint_c, max_setpoint_c)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TableConfig, default_rate_dps, default_accel_dps2, max_rate_dps,
                                   max_accel_dps2, max_move_deg)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(AdcConfig, bits, vref_v, supply_divider)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SupplyConfig, nominal_v, ripple_v, ripple_hz, drift_std_v,
                                   drift_tau_s, noise_v)

nlohmann::json ConfigJson(const RigConfig& c) {
    using nlohmann::json;
    json j;
    j["seed"] = c.seed;
    j["noise_seed"] = c.NoiseSeed();
    j["sensor_ids"] = c.UnitIds();
    j["sample_rate_hz"] = c.sample_rate_hz;
    j["start_utime"] = c.start_utime;
    j["chamber_state_hz"] = c.chamber_state_hz;
    j["preset"] = {{"name", c.preset.name},
                   {"range_dps", c.preset.range_dps},
                   {"null_v", c.preset.null_v},
                   {"sensitivity_v_per_dps", c.preset.sensitivity_v_per_dps},
                   {"rail_low_v", c.preset.rail_low_v},
                   {"rail_high_v", c.preset.rail_high_v},
                   {"temp_v_at_25c", c.preset.temp_transfer.v_at_25c},
                   {"temp_v_per_c", c.preset.temp_transfer.v_per_c}};
    j["noise"] = c.noise;
    j["noise"]["noise_density_convention"] = "allan_deviation(tau) = density / sqrt(tau)";
    j["thermal"] = c.thermal;
    j["table"] = c.table;
    j["encoder"] = {{"lines_per_rev", c.encoder.lines_per_rev},
                    {"quadrature", c.encoder.quadrature},
                    {"counts_per_rev", c.encoder.lines_per_rev * c.encoder.quadrature},
                    {"rate_hz", c.encoder.rate_hz}};
    j["adc"] = c.adc;
    j["supply"] = c.supply;
    return j;
}

namespace {

nlohmann::json EffectsJson(const EffectsConfig& e) {
    using nlohmann::json;
    auto one = [](double value, const char* unit, const char* what) {
        return json{{"on", value != 0.0}, {"value", value}, {"unit", unit}, {"model", what}};
    };
    json j;
    j["temp_rate"] = one(e.temp_rate_v_per_c_per_min, "V/(degC/min)",
                         "offset_v += value * dT_die/dt [degC/min]");
    j["hysteresis"] = one(e.hysteresis_v, "V",
                          "offset_v += value/2 * branch; branch in [-1,1] from a play operator of "
                          "width hysteresis_width_c on T_die (+1 heating, -1 cooling)");
    j["hysteresis"]["width_c"] = e.hysteresis_width_c;
    j["temp_cubic"] = one(e.temp_cubic_v_per_c3, "V/K^3", "offset_v += value * (T_die - 25)^3");
    j["supply"] =
        one(e.supply_v_per_v, "V/V", "offset_v += value * (supply_true_v - supply.nominal_v)");
    j["sf_asymmetry"] = one(e.sf_asymmetry, "1",
                            "sensitivity *= 1 + value/2 for positive rate, 1 - value/2 negative");
    j["warmup"] = one(e.warmup_v, "V", "offset_v += value * exp(-t_since_power_on / tau_s)");
    j["warmup"]["tau_s"] = e.warmup_tau_s;
    j["aging"] = one(e.aging_v_per_h, "V/h", "offset_v += value * t_since_power_on [h]");
    j["compressor"] =
        one(e.compressor_v, "V", "offset_v += value * sin(2 pi t_since_power_on / period_s)");
    j["compressor"]["period_s"] = e.compressor_period_s;
    j["gsens"] = one(e.gsens_v_per_g, "V/g",
                     "offset_v += value * sin(tilt_deg) * cos(table_angle_deg) [g: gravity's "
                     "component in the sensor's plane through the tilted table axis]");
    j["gsens"]["tilt_deg"] = e.tilt_deg;
    j["hysteresis_smooth"] =
        one(e.hysteresis_smooth_v, "V",
            "offset_v += value/2 * b; b in (-1,1), 0 at power-on, db/d|dT_die| = (sign(dT_die) - "
            "b) / travel_c: the branch turns over exponentially in the temperature travel");
    j["hysteresis_smooth"]["travel_c"] = e.hysteresis_travel_c;
    j["warmup2"] = one(e.warmup2_v, "V", "offset_v += value * exp(-t_since_power_on / tau_s)");
    j["warmup2"]["tau_s"] = e.warmup2_tau_s;
    // Which of them the analysis has a candidate term for, and for which with the same shape.
    for (const char* n :
         {"temp_rate", "hysteresis", "temp_cubic", "supply", "sf_asymmetry", "warmup"})
        j[n]["analysis"] = "candidate";
    for (const std::string& n : OutsideEffectNames()) j[n]["analysis"] = "outside the list";
    j["hysteresis_smooth"]["analysis"] = "candidate-shaped (hysteresis), another shape";
    j["warmup2"]["analysis"] = "candidate-shaped (warmup), a second time constant";
    return j;
}

}  // namespace

nlohmann::json TruthJson(const Rig& rig) {
    using nlohmann::json;
    const RigConfig& c = rig.config();
    json j;
    j["format"] = "gyrocal-sim-truth/1";
    j["seed"] = c.seed;
    j["noise_seed"] = c.NoiseSeed();
    j["start_utime"] = c.start_utime;
    j["truth_temperature"] = "die_c";
    j["truth_temperature_note"] =
        "curves are functions of the DIE temperature T_die (chamber air through the package lag), "
        "not of the reported temp_c: temp_c = T_die through the sensor lag (sensor_tau_s) + "
        "temp_sensor_offset_c + noise, quantized";
    j["t0_c"] = kTruthT0C;
    j["noise_note"] =
        "offset_v excludes the rate noise: bias instability and rate random walk (config.noise) "
        "wander about zero on top of it, in deg/s times the sensitivity";
    j["effects"] = EffectsJson(c.effects);
    j["config"] = ConfigJson(c);
    json units = json::array();
    for (const UnitTruth& u : rig.units()) {
        json ju;
        ju["sensor_id"] = u.sensor_id;
        ju["offset_v"] = {{"terms", {"1", "dT", "dT^2"}},
                          {"coeffs", u.offset_coeffs},
                          {"t0_c", kTruthT0C},
                          {"temperature", "die_c"}};
        ju["sensitivity_v_per_dps"] = {{"terms", {"1", "dT", "dT^2"}},
                                       {"coeffs", u.sensitivity_coeffs},
                                       {"t0_c", kTruthT0C},
                                       {"temperature", "die_c"}};
        ju["temp_sensor_offset_c"] = u.temp_sensor_offset_c;
        ju["package_tau_s"] = u.package_tau_s;
        json table = json::array();
        for (int t = -40; t <= 85; t += 5) {
            table.push_back({{"die_c", t},
                             {"offset_v", u.OffsetV(t)},
                             {"sensitivity_v_per_dps", u.SensitivityVPerDps(t)}});
        }
        ju["table"] = table;
        units.push_back(ju);
    }
    j["units"] = units;
    return j;
}

}  // namespace gyrocal::sim
