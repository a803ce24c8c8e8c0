#pragma once
// Options of othersim, an independent generator of measured-looking gyro calibration data.
//
// It is written apart from producers/sim on purpose (no code, constants or noise model shared):
// the pipeline must be judged on data it did not make. Its rig differs in every part:
//   chamber   a controller with a second-order response that overshoots the end of each ramp,
//             plus a slow Ornstein-Uhlenbeck wander of the air
//   thermal   two nodes: the board follows the air (board_tau_s), the die follows the board
//             (die_tau_s) and sits self_heating_c above it once powered; the temperature output
//             reads the die through its own first-order lag, with a per-unit gain and offset
//   gyro      offset and sensitivity are smooth non-polynomial curves of the die temperature
//             (cubic + exponential parts), a power-on warm-up, an optional supply and thermal-
//             gradient effect; a two-pole output low-pass
//   noise     white + flicker (a bank of 8 OU processes at ratio 3 in correlation time, scaled
//             to a flat Allan level) + rate random walk, in deg/s, through the low-pass
//   ADC       12 bits over a 4.096 V reference behind a 0.8 divider (1.25 mV steps)
//   table     trapezoidal +turn/-turn moves at each dwell's end; an optical encoder of its own
//             resolution; optional slip of the encoder during one turn
//   faults    a disturbance (an offset shift) during one dwell of one unit or all
// Output: the project's CSV import format and a truth JSON beside it (never in the CSV).
#include <cstdint>
#include <string>
#include <vector>

namespace gyrocal::othersim {

// One step of the chamber profile: ramp to setpoint_c, hold dwell_s, then (turns) a +turn and a
// -turn of the table. A ramp-only step: dwell_s 0 and turns false.
struct Step {
    double setpoint_c = 25.0;  // [degC] chamber target
    double dwell_s = 600.0;    // [s] hold after the ramp reference reaches the setpoint
    bool turns = true;         // the +turn/-turn pair at the end of the dwell
};

struct ProfileOptions {
    std::vector<Step> steps;
    double start_c = 25.0;               // [degC] room temperature at power-on (air, board, die)
    double lead_in_s = 60.0;             // [s] powered at room temperature before the first ramp
    double ramp_c_per_min = 2.0;         // [degC/min] ramp of the controller's reference
    double turn_deg = 90.0;              // [deg] each turn (+ then -)
    double turn_rate_dps = 45.0;         // [deg/s] cruise rate
    double turn_accel_dps2 = 90.0;       // [deg/s^2]
    double pause_between_turns_s = 8.0;  // [s] at rest between the + and the - turn
    double rest_after_turns_s = 8.0;     // [s] at rest after the pair, before the next ramp
    double tail_s = 30.0;                // [s] recorded after the last step
};

struct ThermalOptions {
    double chamber_period_s = 240.0;  // [s] natural period of the controller's response
    double chamber_damping = 0.45;    // [1] damping ratio (< 1: overshoot)
    double air_wander_c = 0.03;       // [degC] OU wander of the air (1 sigma)
    double air_wander_tau_s = 45.0;   // [s] its correlation time
    double board_tau_s = 150.0;       // [s] board behind the air
    double die_tau_s = 25.0;          // [s] die behind the board
    double self_heating_c = 1.2;      // [degC] die above board when powered (nominal)
    double temp_line_tau_s = 1.0;     // [s] temperature output behind the die
};

struct NoiseOptions {
    double white_dps_rthz = 0.04;       // [deg/s/sqrt(Hz)] white rate noise (Allan rho / sqrt(tau))
    double flicker_dps = 0.007;         // [deg/s] flat Allan deviation level of the OU bank
    double rrw_dps_rts = 3e-5;          // [deg/s/sqrt(s)] rate random walk
    double lpf_hz = 35.0;               // [Hz] corner of each of the two output poles
    double temp_line_noise_v = 0.0004;  // [V] white noise on the temperature line (1 sigma)
};

struct AdcOptions {
    int bits = 12;                // [bits] 0 = write the analog volts unquantised
    double vref_v = 4.096;        // [V] full scale
    double divider = 0.8;         // [1] gyro and temperature lines are read through this divider
    double supply_divider = 0.5;  // [1] supply read through this divider
};

struct SupplyOptions {
    bool write = true;            // write the supply_v column
    double nominal_v = 5.0;       // [V]
    double wander_v = 0.02;       // [V] slow OU wander (1 sigma)
    double wander_tau_s = 900.0;  // [s]
    double read_noise_v = 0.001;  // [V] measurement noise
};

// How units differ (1 sigma, or scales of their draws).
struct SpreadOptions {
    double null_sd_v = 0.04;                // [V] offset at 25 degC about 2.5 V
    double slope_sd_v = 0.02;               // [V] offset change per 50 degC (linear part)
    double curve_sd_v = 0.004;              // [V] quadratic part at +-50 degC
    double cubic_sd_v = 0.0015;             // [V] cubic part at +-50 degC
    double cold_bend_sd_v = 0.002;          // [V] exponential part at the cold end
    double cold_bend_c = 15.0;              // [degC] its e-folding temperature above -40 degC
    double sens_nominal_v_per_dps = 0.006;  // [V/(deg/s)]
    double sens_sd_frac = 0.025;            // [1] sensitivity at 25 degC
    double sens_slope_sd_frac = 0.01;       // [1] relative change per 50 degC
    double sens_curve_sd_frac = 0.003;      // [1] quadratic part at +-50 degC
    double sens_cubic_sd_frac = 0.001;      // [1] cubic part at +-50 degC
    double temp_offset_sd_c = 1.5;          // [degC] temperature output offset
    double temp_gain_sd_frac = 0.01;        // [1] temperature output gain about 9 mV/K
};

// Effects none of the pipeline's lists has to know about (0 = off).
struct EffectOptions {
    double warmup_v = 0.0003;       // [V] offset at power-on, decaying with warmup_tau_s
    double warmup_tau_s = 300.0;    // [s]
    double gradient_v_per_c = 0.0;  // [V/degC] offset += k * (board - die + self heating)
    double supply_v_per_v = 0.0;    // [V/V] offset += k * (supply - nominal)
    // Outside any candidate list (README.md#effects-outside-the-list):
    double drift_v_per_h = 0.0;         // [V/h] aging: offset += k * t (package stress relaxing)
    double periodic_v = 0.0;            // [V] amplitude of an offset at periodic_s (the chamber
    double periodic_s = 600.0;          //     compressor's duty cycle coupling through the mount)
    double periodic_phase_rad = 0.0;    // [rad]
    double step_v = 0.0;                // [V] offset step at step_at_s (a mount screw settling)
    double step_at_s = 0.0;             // [s]
    double warmup2_v = 0.0;             // [V] a second, slow warm-up exp(-t / warmup2_tau_s)
    double warmup2_tau_s = 3000.0;      // [s] (the regulator board's thermal time constant)
    double OutsideV(double t_s) const;  // [V] the sum of the four at time t_s
};

// An offset shift of one unit (sensor_id) or all (""), during one dwell: from start_after_s
// into the dwell for duration_s (<= 0: until the dwell's turns begin).
struct Disturbance {
    int dwell_index = 0;
    std::string sensor_id;
    double offset_v = 0.003;  // [V]
    double start_after_s = 0.0;
    double duration_s = 0.0;
};

// The encoder loses slip_deg during turn turn_index (0-based over all turns of the run): its disk
// stops following the table for slip_deg / turn_rate_dps seconds in the middle of the cruise.
struct Slip {
    int turn_index = 0;
    double slip_deg = 3.0;  // [deg] > 0
};

struct FaultOptions {
    std::vector<Disturbance> disturbances;
    std::vector<Slip> slips;
};

struct Options {
    uint64_t seed = 1;
    // 0: the noise, chamber wander and supply follow `seed`; another value: the same units (drawn
    // from `seed`) with fresh noise, as a second run of the same units (a held-out run).
    uint64_t noise_seed = 0;
    int units = 2;
    std::string id_prefix = "U";            // sensor ids U1, U2, ...
    double sample_rate_hz = 100.0;          // [Hz] every unit and the encoder, sampled together
    double encoder_counts_per_rev = 14400;  // [count/rev] 3600 lines x4
    ProfileOptions profile;
    ThermalOptions thermal;
    NoiseOptions noise;
    AdcOptions adc;
    SupplyOptions supply;
    SpreadOptions spread;
    EffectOptions effects;
    FaultOptions faults;

    // The lab profile: 25, -10, 10, 30, 50, 70, 25 degC, each with dwell_s and turns.
    static Options ReturnToStart(double dwell_s = 900.0);
    // The same profile on a fast thermal path (20 Hz sampling, 8 Hz filter, board tau 40 s, die
    // tau 8 s, 120 s chamber period, 8 degC/min ramps), so that dwells of minutes settle: for
    // tests that need a whole run in seconds.
    static Options QuickReturnToStart(double dwell_s);
    // "" when valid, else one sentence naming the option (as the CLI spells it) and what is valid.
    std::string Validate() const;
    std::vector<std::string> SensorIds() const;
};

// Parses "25,-10,10" into steps of dwell_s each (with turns). Throws std::invalid_argument naming
// the item that is not a number in -60..150 degC.
std::vector<Step> ParseSetpoints(const std::string& list, double dwell_s, bool turns);

}  // namespace gyrocal::othersim
