#pragma once
// Configuration of the simulated rig: gyro module preset, per-unit spread, noise, thermal
// physics, turntable, encoder, ADC, supply, and the undeclared effects. Plain data with defaults;
// Validate() refuses out-of-range values with a message that names the option and the valid range.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "producers/sensor/temp_transfer.hpp"

namespace gyrocal::sim {

// A refused configuration; what() names the option (as spelled on the command line) and what is
// valid.
class ConfigError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

// Nominal datasheet figures of one gyro module type (the seed's METHOD.md: its facts worth
// knowing).
struct GyroPreset {
    std::string name;                      // "610" (myGyro610EB/ADXRS610) or "613"
    double range_dps = 300.0;              // [deg/s] measuring range; the rate saturates beyond it
    double null_v = 2.5;                   // [V] nominal null (zero-rate) output at 25 degC
    double sensitivity_v_per_dps = 0.006;  // [V/(deg/s)] nominal sensitivity at 25 degC
    double rail_low_v = 0.25;              // [V] lowest output swing
    double rail_high_v = 4.75;             // [V] highest output swing
    sensor::TempTransfer temp_transfer;    // temperature output, volts <-> degC
};

// "610" or "613"; throws ConfigError naming --preset and the valid names otherwise.
GyroPreset PresetByName(const std::string& name);

// How much units differ from the preset (1-sigma or bounds of the seeded draw), and the truth
// curve reference temperature. Magnitudes follow ADXRS61x datasheet figures.
struct SpreadConfig {
    double null_std_v = 0.03;                 // [V] null at 25 degC: preset + N(0, this)
    double offset_tc_min_v_per_c = 0.1e-3;    // [V/K] |linear offset drift| drawn in [min, max]
    double offset_tc_max_v_per_c = 1.0e-3;    // [V/K]
    double offset_tc2_min_v_per_c2 = 1.0e-6;  // [V/K^2] |quadratic offset term| in [min, max]
    double offset_tc2_max_v_per_c2 = 6.0e-6;  // [V/K^2]
    double sens_std_frac = 0.03;              // [1] sensitivity at 25 degC: nominal*(1+N(0,this))
    double sens_tc_min_per_c = 1.0e-4;        // [1/K] |relative linear sensitivity drift|
    double sens_tc_max_per_c = 4.0e-4;        // [1/K]
    double sens_tc2_min_per_c2 = 1.0e-6;      // [1/K^2] |relative quadratic sensitivity term|
    double sens_tc2_max_per_c2 = 3.0e-6;      // [1/K^2]
    double temp_sensor_offset_std_c = 2.0;    // [degC] per-unit temperature sensor offset
    double package_tau_spread_frac = 0.05;    // [1] per-unit package lag: tau*(1+N(0,this))
};

// Rate noise of a MEMS gyro. Convention: noise density rho is the angle-random-walk coefficient,
// sigma_Allan(tau) = rho / sqrt(tau) (ADI's ARW[deg/sqrt(h)] = 60 * rho).
struct NoiseConfig {
    double noise_density_dps_rthz = 0.05;  // [deg/s/sqrt(Hz)] white rate noise
    double bias_instability_dps = 0.008;   // [deg/s] level of the flat part of the Allan deviation
    double rate_random_walk_dps_rts = 5e-5;  // [deg/s/sqrt(s)] rate random walk
    double lpf_hz = 40.0;                    // [Hz] module output low-pass (first order); 0 = none
    double temp_noise_v = 0.0003;            // [V] white noise on the temperature line (1 sigma)
};

struct ThermalConfig {
    double start_temp_c = 25.0;     // [degC] chamber air, package and sensor at power-on
    double ramp_c_per_min = 3.0;    // [degC/min] chamber's own ramp-rate limit
    double air_tau_s = 30.0;        // [s] air settling lag behind the ramp reference
    double air_noise_c = 0.02;      // [degC] chamber control fluctuation (1 sigma, OU process)
    double air_noise_tau_s = 20.0;  // [s] correlation time of that fluctuation
    double package_tau_s = 200.0;   // [s] die lag behind the air (package thermal time constant)
    double sensor_tau_s = 15.0;     // [s] temperature sensor lag behind the die
    double setpoint_tolerance_c = 0.5;  // [degC] |air - setpoint| for at_setpoint
    double min_setpoint_c = -45.0;      // [degC] lowest setpoint the chamber accepts
    double max_setpoint_c = 90.0;       // [degC] highest setpoint the chamber accepts
};

struct TableConfig {
    double default_rate_dps = 30.0;    // [deg/s] cruise rate when a command gives <= 0
    double default_accel_dps2 = 60.0;  // [deg/s^2] acceleration when a command gives <= 0
    double max_rate_dps = 180.0;       // [deg/s] faster orders are refused
    double max_accel_dps2 = 500.0;     // [deg/s^2] harder orders are refused
    double max_move_deg = 3600.0;      // [deg] larger relative moves are refused
};

struct EncoderConfig {
    int32_t lines_per_rev = 2500;  // [lines/rev] optical disk lines
    int32_t quadrature = 4;        // [1] counts per line (1, 2 or 4)
    double rate_hz = 100.0;        // [Hz] publication rate
};

struct AdcConfig {
    int bits = 16;                // [bits] resolution; 0 = no ADC (raw analog volts)
    double vref_v = 5.0;          // [V] full scale, input range 0..vref
    double supply_divider = 0.5;  // [1] supply is read through this divider
};

struct SupplyConfig {
    double nominal_v = 5.0;      // [V]
    double ripple_v = 0.002;     // [V] ripple amplitude
    double ripple_hz = 120.0;    // [Hz] ripple frequency (full-wave rectified 60 Hz)
    double drift_std_v = 0.01;   // [V] slow drift (1 sigma, OU process)
    double drift_tau_s = 600.0;  // [s] correlation time of the drift
    double noise_v = 0.0005;     // [V] measurement noise of supply_v (1 sigma)
};

// Effects the seed's model lacks. Each is off at 0 (the default) and then costs nothing and draws
// no random numbers, so output stays bit-identical. producers/sim/README.md gives each one's
// formula and why it is plausible. Magnitudes, when on:
struct EffectsConfig {
    // The analysis' six candidates, term for term:
    double temp_rate_v_per_c_per_min = 0.0;  // offset += k * dT_die/dt            [V/(degC/min)]
    double hysteresis_v = 0.0;               // heating and cooling branches this far apart [V]
    double temp_cubic_v_per_c3 = 0.0;        // offset += k * (T_die - 25)^3       [V/K^3]
    double supply_v_per_v = 0.0;             // offset += k * (supply - nominal)   [V/V]
    double sf_asymmetry = 0.0;               // sensitivity * (1 +- k/2) for +/- rate   [1]
    double warmup_v = 0.0;                   // offset += k * exp(-t_on / warmup_tau_s) [V]
    double hysteresis_width_c = 2.0;         // [degC] reversal needed to change branch
    double warmup_tau_s = 300.0;             // [s] warm-up transient time constant
    // Outside the candidate list:
    double aging_v_per_h = 0.0;          // offset += k * t_on [h] (package stress relaxation)
    double compressor_v = 0.0;           // offset += k * sin(2 pi t_on / compressor_period_s) [V]
    double compressor_period_s = 600.0;  // [s] the chamber compressor's on/off cycle
    double gsens_v_per_g = 0.0;          // offset += k * sin(tilt) * cos(table angle)  [V/g]
    double tilt_deg = 2.0;               // [deg] tilt of the table's axis from the vertical
    // Candidate-shaped, with another shape than the analysis' term:
    double hysteresis_smooth_v = 0.0;  // branches k apart, reached exponentially over a travel [V]
    double hysteresis_travel_c = 3.0;  // [degC] travel that brings the branch 63 % of the way
    double warmup2_v = 0.0;            // a second warm-up: offset += k * exp(-t_on / tau2)  [V]
    double warmup2_tau_s = 1500.0;     // [s] its time constant

    bool AnyOn() const;
};

// Effect names (their magnitudes) accepted by SetEffect / --effect NAME=VALUE.
const std::vector<std::string>& EffectNames();
// Shape parameters also accepted there (hysteresis_width_c, warmup_tau_s, compressor_period_s,
// tilt_deg, hysteresis_travel_c, warmup2_tau_s), so that a shape travels with its effect through
// `gyrocal calibrate --effect`.
const std::vector<std::string>& EffectShapeNames();
// The effects the analysis has no candidate for (aging, compressor, gsens).
const std::vector<std::string>& OutsideEffectNames();
// Sets one effect's magnitude or shape by name; throws ConfigError naming --effect and the valid
// names (unknown name) or the valid range (bad value).
void SetEffect(EffectsConfig& effects, const std::string& name, double value);
// Parses "NAME=VALUE" and sets it; throws ConfigError on bad form, name or value.
void ParseEffect(EffectsConfig& effects, const std::string& name_equals_value);

struct RigConfig {
    uint64_t seed = 1;  // draws the units (their truth) and, unless noise_seed is set, the noise
    // Draws the noise alone (rate noise, chamber air, supply, encoder phase): the same units with
    // a fresh realisation, for repeatability studies. 0 = use seed (the default, bit-identical to
    // a rig without this option).
    uint64_t noise_seed = 0;
    uint64_t NoiseSeed() const { return noise_seed != 0 ? noise_seed : seed; }
    int num_units = 4;                    // units S01..S<n>
    std::vector<std::string> sensor_ids;  // empty = S01..S<num_units>; else overrides num_units
    double sample_rate_hz = 100.0;        // [Hz] gyro sample rate, all units sampled together
    int64_t start_utime = 1'000'000'000'000'000;  // [us] simulated clock at power-on
    double chamber_state_hz = 1.0;                // [Hz] CHAMBER_STATE rate (simulated time)
    GyroPreset preset = PresetByName("610");
    SpreadConfig spread;
    NoiseConfig noise;
    ThermalConfig thermal;
    TableConfig table;
    EncoderConfig encoder;
    AdcConfig adc;
    SupplyConfig supply;
    EffectsConfig effects;

    static RigConfig Defaults() { return {}; }
    // The ids the rig will use (sensor_ids, or S01..S<num_units>).
    std::vector<std::string> UnitIds() const;
    // Throws ConfigError naming the first bad option and its valid range.
    void Validate() const;
};

}  // namespace gyrocal::sim
