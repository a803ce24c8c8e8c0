#include "producers/sim/config.hpp"

#include <cmath>
#include <initializer_list>
#include <string>

#include "lcmtypes/channels/channels.hpp"
#include "lcmtypes/text/number.hpp"

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

// Which end of a Limit is in range: kFrom lo <= value, kAbove lo < value (a zero time constant,
// rate or width has no meaning); value <= hi either way.
enum Low { kFrom, kAbove };

void CheckRange(const char* option, double value, Low low, double lo, double hi) {
    if (low == kAbove) {
        RangeOpenLow(option, value, lo, hi);
    } else {
        Range(option, value, lo, hi);
    }
}

// One option of a config section and its valid range.
template <class Config>
struct Limit {
    const char* option;
    double Config::*field;
    Low low;
    double lo, hi;
};

// Refuses the first field of `c` outside its limit, in the order given.
template <class Config>
void CheckLimits(const Config& c, std::initializer_list<Limit<Config>> limits) {
    for (const Limit<Config>& l : limits) CheckRange(l.option, c.*l.field, l.low, l.lo, l.hi);
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
    const char* option = nullptr;  // a shape's own option of the rig, if it has one
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
        {"hysteresis_width_c", &E::hysteresis_width_c, "degC", 0.0, 50.0, true,
         "--hysteresis-width-c"},
        {"warmup_tau_s", &E::warmup_tau_s, "s", 0.0, 1e5, true, "--warmup-tau-s"},
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
        CheckRange(option.c_str(), value, f.shape ? kAbove : kFrom, f.lo, f.hi);
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
    for (int i = 1; i <= num_units; ++i) ids.push_back(text::Printf("S%02d", i));
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
        if (!channels::IsValidSensorId(id)) {
            throw ConfigError("--sensor-ids: '" + id +
                              "' is not a valid sensor id; valid: 1..32 of A-Z a-z 0-9 _ -");
        }
    }
}

void CheckNoise(const NoiseConfig& noise) {
    using N = NoiseConfig;
    CheckLimits(noise, {{"--noise-density-dps-rthz", &N::noise_density_dps_rthz, kFrom, 0.0, 10.0},
                        {"--bias-instability-dps", &N::bias_instability_dps, kFrom, 0.0, 10.0},
                        {"--rrw-dps-rts", &N::rate_random_walk_dps_rts, kFrom, 0.0, 1.0},
                        {"--lpf-hz", &N::lpf_hz, kFrom, 0.0, 100000.0},
                        {"--temp-noise-v", &N::temp_noise_v, kFrom, 0.0, 0.1}});
}

void CheckThermal(const ThermalConfig& t) {
    using T = ThermalConfig;
    CheckLimits(t, {{"--start-temp-c", &T::start_temp_c, kFrom, t.min_setpoint_c, t.max_setpoint_c},
                    {"--ramp-c-per-min", &T::ramp_c_per_min, kAbove, 0.0, 1000.0},
                    {"--air-tau-s", &T::air_tau_s, kAbove, 0.0, 1e5},
                    {"--air-noise-c", &T::air_noise_c, kFrom, 0.0, 5.0},
                    {"--air-noise-tau-s", &T::air_noise_tau_s, kAbove, 0.0, 1e5},
                    {"--package-tau-s", &T::package_tau_s, kAbove, 0.0, 1e5},
                    {"--sensor-tau-s", &T::sensor_tau_s, kAbove, 0.0, 1e5},
                    {"--setpoint-tolerance-c", &T::setpoint_tolerance_c, kAbove, 0.0, 20.0},
                    {"--min-setpoint-c", &T::min_setpoint_c, kFrom, -100.0, t.max_setpoint_c},
                    {"--max-setpoint-c", &T::max_setpoint_c, kFrom, t.min_setpoint_c, 200.0}});
}

void CheckSpread(const SpreadConfig& spread) {
    using S = SpreadConfig;
    CheckLimits(spread,
                {{"--spread-null-std-v", &S::null_std_v, kFrom, 0.0, 0.5},
                 {"--temp-sensor-offset-std-c", &S::temp_sensor_offset_std_c, kFrom, 0.0, 20.0},
                 {"--package-tau-spread-frac", &S::package_tau_spread_frac, kFrom, 0.0, 0.3},
                 {"--sens-std-frac", &S::sens_std_frac, kFrom, 0.0, 0.3}});
}

void CheckTableAndEncoder(const TableConfig& table, const EncoderConfig& encoder) {
    using T = TableConfig;
    CheckLimits(table,
                {{"--table-max-rate-dps", &T::max_rate_dps, kAbove, 0.0, 2000.0},
                 {"--table-max-accel-dps2", &T::max_accel_dps2, kAbove, 0.0, 1e5},
                 {"--table-rate-dps", &T::default_rate_dps, kAbove, 0.0, table.max_rate_dps},
                 {"--table-accel-dps2", &T::default_accel_dps2, kAbove, 0.0, table.max_accel_dps2},
                 {"--table-max-move-deg", &T::max_move_deg, kAbove, 0.0, 1e6}});

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
    CheckLimits(adc, {{"--adc-vref-v", &AdcConfig::vref_v, kAbove, 0.0, 50.0},
                      {"--adc-supply-divider", &AdcConfig::supply_divider, kAbove, 0.0, 1.0}});

    using S = SupplyConfig;
    CheckLimits(supply, {{"--supply-nominal-v", &S::nominal_v, kAbove, 0.0, 50.0},
                         {"--supply-ripple-v", &S::ripple_v, kFrom, 0.0, 1.0},
                         {"--supply-ripple-hz", &S::ripple_hz, kAbove, 0.0, 1e6},
                         {"--supply-drift-std-v", &S::drift_std_v, kFrom, 0.0, 1.0},
                         {"--supply-drift-tau-s", &S::drift_tau_s, kAbove, 0.0, 1e6},
                         {"--supply-noise-v", &S::noise_v, kFrom, 0.0, 1.0}});
}

// The shapes' ranges are --effect's (EffectFields); those with an option of their own are named
// by it.
void CheckEffectShapes(const EffectsConfig& effects) {
    for (const EffectField& f : EffectFields()) {
        if (!f.shape) continue;
        const std::string option = f.option ? f.option : "--effect " + std::string(f.name);
        RangeOpenLow(option.c_str(), effects.*f.field, f.lo, f.hi);
    }
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
