#include "config.hpp"

#include <cmath>
#include <cstdio>

#include "bus_free_ids.hpp"
#include "text/number.hpp"

namespace gyrocal::sim {

namespace {

// Refuses `value` of `option` unless lo <= value <= hi (and finite).
void Range(const char* option, double value, double lo, double hi) {
    if (!std::isfinite(value) || value < lo || value > hi) {
        throw ConfigError(std::string(option) + " = " + text::Sig(value) +
                          " is out of range; valid: " + text::Sig(lo) + " .. " + text::Sig(hi));
    }
}

// Refuses unless lo < value <= hi.
void RangeOpenLow(const char* option, double value, double lo, double hi) {
    if (!std::isfinite(value) || value <= lo || value > hi) {
        throw ConfigError(std::string(option) + " = " + text::Sig(value) +
                          " is out of range; valid: > " + text::Sig(lo) +
                          " and <= " + text::Sig(hi));
    }
}

}  // namespace

GyroPreset PresetByName(const std::string& name) {
    GyroPreset p;
    p.name = name;
    if (const auto transfer = sensor::PresetTransfer(name)) p.temp_transfer = *transfer;
    if (name == "610") {  // myGyro610EB, ADXRS610
        p.range_dps = 300.0;
        p.sensitivity_v_per_dps = 0.006;
    } else if (name == "613") {  // myGyro613EB, ADXRS613
        p.range_dps = 150.0;
        p.sensitivity_v_per_dps = 0.0125;
    } else {
        throw ConfigError("--preset '" + name +
                          "' is unknown; valid: 610 (myGyro610EB, ADXRS610), "
                          "613 (myGyro613EB, ADXRS613)");
    }
    return p;
}

bool EffectsConfig::AnyOn() const {
    return temp_rate_v_per_c_per_min != 0.0 || hysteresis_v != 0.0 || temp_cubic_v_per_c3 != 0.0 ||
           supply_v_per_v != 0.0 || sf_asymmetry != 0.0 || warmup_v != 0.0 ||
           aging_v_per_h != 0.0 || compressor_v != 0.0 || gsens_v_per_g != 0.0 ||
           hysteresis_smooth_v != 0.0 || warmup2_v != 0.0;
}

namespace {

// One name of --effect: the field it sets and its valid range. Bounds of magnitudes: far beyond
// anything physical, only to catch typos (a value in mV instead of V). Shapes: > lo (a zero
// width, period or time constant has no meaning) and <= hi.
struct EffectField {
    const char* name;
    double EffectsConfig::*field;
    const char* unit;
    double lo, hi;
    bool shape;
};

const std::vector<EffectField>& EffectFields() {
    using E = EffectsConfig;
    static const std::vector<EffectField> fields = {
        {"temp_rate", &E::temp_rate_v_per_c_per_min, "V/(degC/min)", -0.1, 0.1, false},
        {"hysteresis", &E::hysteresis_v, "V", -0.5, 0.5, false},
        {"temp_cubic", &E::temp_cubic_v_per_c3, "V/K^3", -1e-5, 1e-5, false},
        {"supply", &E::supply_v_per_v, "V/V", -1.0, 1.0, false},
        {"sf_asymmetry", &E::sf_asymmetry, "1", -0.5, 0.5, false},
        {"warmup", &E::warmup_v, "V", -0.5, 0.5, false},
        {"aging", &E::aging_v_per_h, "V/h", -0.1, 0.1, false},
        {"compressor", &E::compressor_v, "V", -0.5, 0.5, false},
        {"gsens", &E::gsens_v_per_g, "V/g", -1.0, 1.0, false},
        {"hysteresis_smooth", &E::hysteresis_smooth_v, "V", -0.5, 0.5, false},
        {"warmup2", &E::warmup2_v, "V", -0.5, 0.5, false},
        {"hysteresis_width_c", &E::hysteresis_width_c, "degC", 0.0, 50.0, true},
        {"warmup_tau_s", &E::warmup_tau_s, "s", 0.0, 1e5, true},
        {"compressor_period_s", &E::compressor_period_s, "s", 1.0, 1e5, true},
        {"tilt_deg", &E::tilt_deg, "deg", 0.0, 90.0, true},
        {"hysteresis_travel_c", &E::hysteresis_travel_c, "degC", 0.0, 50.0, true},
        {"warmup2_tau_s", &E::warmup2_tau_s, "s", 0.0, 1e5, true},
    };
    return fields;
}

std::vector<std::string> FieldNames(bool shape) {
    std::vector<std::string> n;
    for (const EffectField& f : EffectFields())
        if (f.shape == shape) n.emplace_back(f.name);
    return n;
}

}  // namespace

const std::vector<std::string>& EffectNames() {
    static const std::vector<std::string> names = FieldNames(false);
    return names;
}

const std::vector<std::string>& EffectShapeNames() {
    static const std::vector<std::string> names = FieldNames(true);
    return names;
}

const std::vector<std::string>& OutsideEffectNames() {
    static const std::vector<std::string> names = {"aging", "compressor", "gsens"};
    return names;
}

void SetEffect(EffectsConfig& e, const std::string& name, double value) {
    for (const EffectField& f : EffectFields()) {
        if (name != f.name) continue;
        const std::string option = "--effect " + name + " [" + f.unit + "]";
        if (f.shape) {
            RangeOpenLow(option.c_str(), value, f.lo, f.hi);
        } else {
            Range(option.c_str(), value, f.lo, f.hi);
        }
        e.*f.field = value;
        return;
    }
    std::string valid, shapes;
    for (const auto& n : EffectNames()) valid += (valid.empty() ? "" : ", ") + n;
    for (const auto& n : EffectShapeNames()) shapes += (shapes.empty() ? "" : ", ") + n;
    throw ConfigError("--effect '" + name + "' is unknown; valid names: " + valid +
                      "; shapes: " + shapes);
}

void ParseEffect(EffectsConfig& effects, const std::string& text) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
        throw ConfigError("--effect '" + text + "': expected NAME=VALUE, e.g. temp_cubic=2e-8");
    }
    const std::string name = text.substr(0, eq);
    const std::string value_text = text.substr(eq + 1);
    double value = 0.0;
    try {
        size_t used = 0;
        value = std::stod(value_text, &used);
        if (used != value_text.size()) throw std::invalid_argument("trailing characters");
    } catch (const std::exception&) {
        throw ConfigError("--effect '" + text + "': VALUE '" + value_text + "' is not a number");
    }
    SetEffect(effects, name, value);
}

std::vector<std::string> RigConfig::UnitIds() const {
    if (!sensor_ids.empty()) return sensor_ids;
    std::vector<std::string> ids;
    for (int i = 1; i <= num_units; ++i) {
        char buf[16];
        std::snprintf(buf, sizeof buf, "S%02d", i);
        ids.emplace_back(buf);
    }
    return ids;
}

namespace {

// Distinct, channel-safe ids, 1..256 of them.
void CheckUnitIds(const RigConfig& c) {
    if (c.sensor_ids.empty()) Range("--units", c.num_units, 1, 256);
    if (c.sensor_ids.size() > 256) {
        throw ConfigError("--sensor-ids: " + std::to_string(c.sensor_ids.size()) +
                          " ids; valid: 1 .. 256");
    }
    const std::vector<std::string> ids = c.UnitIds();
    for (size_t i = 0; i < ids.size(); ++i) {
        const std::string& id = ids[i];
        for (size_t j = 0; j < i; ++j) {
            if (ids[j] == id) {
                throw ConfigError("--sensor-ids: '" + id +
                                  "' appears twice; valid: distinct ids (each is a channel)");
            }
        }
        if (!IsPlainSensorId(id)) {
            throw ConfigError("--sensor-ids: '" + id +
                              "' is not a valid sensor id; valid: 1..32 of A-Z a-z 0-9 _ -");
        }
    }
}

void CheckNoise(const NoiseConfig& noise) {
    Range("--noise-density-dps-rthz", noise.noise_density_dps_rthz, 0.0, 10.0);
    Range("--bias-instability-dps", noise.bias_instability_dps, 0.0, 10.0);
    Range("--rrw-dps-rts", noise.rate_random_walk_dps_rts, 0.0, 1.0);
    Range("--lpf-hz", noise.lpf_hz, 0.0, 100000.0);
    Range("--temp-noise-v", noise.temp_noise_v, 0.0, 0.1);
}

void CheckThermal(const ThermalConfig& thermal) {
    Range("--start-temp-c", thermal.start_temp_c, thermal.min_setpoint_c, thermal.max_setpoint_c);
    RangeOpenLow("--ramp-c-per-min", thermal.ramp_c_per_min, 0.0, 1000.0);
    RangeOpenLow("--air-tau-s", thermal.air_tau_s, 0.0, 1e5);
    Range("--air-noise-c", thermal.air_noise_c, 0.0, 5.0);
    RangeOpenLow("--air-noise-tau-s", thermal.air_noise_tau_s, 0.0, 1e5);
    RangeOpenLow("--package-tau-s", thermal.package_tau_s, 0.0, 1e5);
    RangeOpenLow("--sensor-tau-s", thermal.sensor_tau_s, 0.0, 1e5);
    RangeOpenLow("--setpoint-tolerance-c", thermal.setpoint_tolerance_c, 0.0, 20.0);
    Range("--min-setpoint-c", thermal.min_setpoint_c, -100.0, thermal.max_setpoint_c);
    Range("--max-setpoint-c", thermal.max_setpoint_c, thermal.min_setpoint_c, 200.0);
}

void CheckSpread(const SpreadConfig& spread) {
    Range("--spread-null-std-v", spread.null_std_v, 0.0, 0.5);
    Range("--temp-sensor-offset-std-c", spread.temp_sensor_offset_std_c, 0.0, 20.0);
    Range("--package-tau-spread-frac", spread.package_tau_spread_frac, 0.0, 0.3);
    Range("--sens-std-frac", spread.sens_std_frac, 0.0, 0.3);
}

void CheckTableAndEncoder(const TableConfig& table, const EncoderConfig& encoder) {
    RangeOpenLow("--table-max-rate-dps", table.max_rate_dps, 0.0, 2000.0);
    RangeOpenLow("--table-max-accel-dps2", table.max_accel_dps2, 0.0, 1e5);
    RangeOpenLow("--table-rate-dps", table.default_rate_dps, 0.0, table.max_rate_dps);
    RangeOpenLow("--table-accel-dps2", table.default_accel_dps2, 0.0, table.max_accel_dps2);
    RangeOpenLow("--table-max-move-deg", table.max_move_deg, 0.0, 1e6);

    Range("--encoder-lines", encoder.lines_per_rev, 1, 1'000'000);
    if (encoder.quadrature != 1 && encoder.quadrature != 2 && encoder.quadrature != 4) {
        throw ConfigError("--encoder-quadrature = " + std::to_string(encoder.quadrature) +
                          " is not valid; valid: 1, 2 or 4");
    }
    RangeOpenLow("--encoder-hz", encoder.rate_hz, 0.0, 10000.0);
}

void CheckAdcAndSupply(const AdcConfig& adc, const SupplyConfig& supply) {
    Range("--adc-bits", adc.bits, 0, 24);
    if (adc.bits != 0 && adc.bits < 8) {
        throw ConfigError("--adc-bits = " + std::to_string(adc.bits) +
                          " is not valid; valid: 0 "
                          "(no ADC) or 8 .. 24");
    }
    RangeOpenLow("--adc-vref-v", adc.vref_v, 0.0, 50.0);
    RangeOpenLow("--adc-supply-divider", adc.supply_divider, 0.0, 1.0);

    RangeOpenLow("--supply-nominal-v", supply.nominal_v, 0.0, 50.0);
    Range("--supply-ripple-v", supply.ripple_v, 0.0, 1.0);
    RangeOpenLow("--supply-ripple-hz", supply.ripple_hz, 0.0, 1e6);
    Range("--supply-drift-std-v", supply.drift_std_v, 0.0, 1.0);
    RangeOpenLow("--supply-drift-tau-s", supply.drift_tau_s, 0.0, 1e6);
    Range("--supply-noise-v", supply.noise_v, 0.0, 1.0);
}

void CheckEffectShapes(const EffectsConfig& effects) {
    RangeOpenLow("--hysteresis-width-c", effects.hysteresis_width_c, 0.0, 50.0);
    RangeOpenLow("--warmup-tau-s", effects.warmup_tau_s, 0.0, 1e5);
    RangeOpenLow("--effect compressor_period_s", effects.compressor_period_s, 1.0, 1e5);
    RangeOpenLow("--effect tilt_deg", effects.tilt_deg, 0.0, 90.0);
    RangeOpenLow("--effect hysteresis_travel_c", effects.hysteresis_travel_c, 0.0, 50.0);
    RangeOpenLow("--effect warmup2_tau_s", effects.warmup2_tau_s, 0.0, 1e5);
}

}  // namespace

void RigConfig::Validate() const {
    CheckUnitIds(*this);
    RangeOpenLow("--rate-hz", sample_rate_hz, 0.0, 10000.0);
    Range("--start-utime", static_cast<double>(start_utime), 0.0, 4.0e18);
    RangeOpenLow("--chamber-state-hz", chamber_state_hz, 0.0, 1000.0);
    PresetByName(preset.name);  // refuses unknown names
    CheckNoise(noise);
    CheckThermal(thermal);
    CheckSpread(spread);
    CheckTableAndEncoder(table, encoder);
    CheckAdcAndSupply(adc, supply);
    CheckEffectShapes(effects);
}

}  // namespace gyrocal::sim
