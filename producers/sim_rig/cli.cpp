#include "producers/sim_rig/cli.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "lcmtypes/process/flow_options.hpp"
#include "lcmtypes/process/process_main.hpp"
#include "lcmtypes/process/renamed_option.hpp"
#include "producers/sim/builtin_profile.hpp"

namespace gyrocal::sim_rig {

namespace {

// What --help says below the options. The measured speed limits:
// README.md#benchmark-the-simulated-rig-and-the-bus.
const char* kFooter = R"(
Exit codes: 0 normal stop (SIGINT/SIGTERM, --duration-s reached, built-in profile done),
            1 runtime failure (LCM cannot be opened or fails), 2 bad options/configuration.

Time: utime is the simulated clock (us), starting at --start-utime; the wall clock only paces
publication: --speed simulated seconds per wall second, published in batches every --tick-ms.
--speed 0: no fixed speed; the simulation runs as fast as every consumer keeps up (flow control:
each gyrocal process answers the rig's FLOW_MARK messages once handled, and the rig keeps at most
--flow-window-kb unanswered per consumer; one silent for --flow-timeout-s is no longer waited
for). --batch-samples N sends N samples per GYRO_<id> and ENCODER message (any speed).
Speed limit: 4 units at 100 Hz plus the encoder at 100 Hz are 500 messages per simulated second.
UDP multicast has no flow control, so publication is capped at --max-msgs-per-s: with more
subscribers or a busier host, lower it; past the cap the simulation just runs slower (STATUS
extra lag_s), never skipping a sample. The rates the rig and the whole pipeline kept without
loss are measured in producers/sim_rig/README.md; `gyrocal calibrate` picks its --speed from
them.

Truth: per-unit curves (functions of the DIE temperature, about 25 degC), effects and seed go only
to --truth-out, never on the bus.
Effects (off by default; each --effect NAME=VALUE, repeatable):
  temp_rate=V_per_C_per_min  offset += VALUE * dT_die/dt [degC/min]
  hysteresis=V               heating and cooling branches VALUE apart (--hysteresis-width-c)
  temp_cubic=V_per_K3        offset += VALUE * (T_die - 25)^3
  supply=V_per_V             offset += VALUE * (supply - nominal)
  sf_asymmetry=FRACTION      sensitivity * (1 +- VALUE/2) for positive/negative rate
  warmup=V                   offset += VALUE * exp(-t_on / --warmup-tau-s)
Effects outside the analysis' candidate list (producers/sim/README.md says why each):
  aging=V_per_h              offset += VALUE * t_on [h]
  compressor=V               offset += VALUE * sin(2 pi t_on / compressor_period_s)
  gsens=V_per_g              offset += VALUE * sin(tilt_deg) * cos(table angle)
Candidate-shaped, another shape than the analysis' term:
  hysteresis_smooth=V        branches VALUE apart, turned over exponentially in the travel
  warmup2=V                  a second warm-up: offset += VALUE * exp(-t_on / warmup2_tau_s)
Shapes, also as --effect NAME=VALUE (so `gyrocal calibrate --effect` carries them):
  hysteresis_width_c=2 warmup_tau_s=300 compressor_period_s=600 tilt_deg=2
  hysteresis_travel_c=3 warmup2_tau_s=1500
)";

// The options parsed as text, or NaN for "the preset's", resolved into SimRigOptions once
// CLI11 is done (ResolveOptions).
struct RawOptions {
    std::string preset;
    double temp_v_at_25c = NAN, temp_v_per_c = NAN;  // NaN = the preset's
    std::string profile_text = "-10,30,60";
    std::string sensor_ids_text;
    std::vector<std::string> effects;
    long long start_utime = 0;
    unsigned long long seed = 0;
    unsigned long long noise_seed = 0;
};

// An option whose default --help shows.
template <class T>
CLI::Option* AddShown(CLI::App& app, const std::string& name, T& value, const std::string& help) {
    return app.add_option(name, value, help)->capture_default_str();
}

// An option renamed to carry its unit, whose old name keeps working (hidden).
template <class T>
void AddRenamed(CLI::App& app, const std::string& name, const std::string& old_name, T& value,
                const std::string& help) {
    process::AddOldOptionName<T>(app, AddShown(app, name, value, help), old_name, value);
}

// How the process runs: bus, pacing, truth file and seeds.
void AddRunOptions(CLI::App& app, SimRigOptions& o, RawOptions& raw) {
    app.add_option("--lcm-url", o.lcm_url,
                   "LCM provider URL (default $GYROCAL_LCM_URL or LCM's udpm default)");
    AddShown(app, "--mode", o.mode,
             "commanded (obey CHAMBER_CMD/TURNTABLE_CMD) or builtin (run --profile)");
    AddShown(app, "--speed", o.speed,
             "simulated seconds per wall second, <= 100000; 0 = as fast as every consumer "
             "keeps up (flow control)");
    AddShown(app, "--duration-s", o.duration_s, "simulated seconds to run, 0 = until stopped");
    AddShown(app, "--tick-ms", o.tick_ms, "wall milliseconds between publication batches, 1..100");
    AddShown(app, "--max-msgs-per-s", o.max_msgs_per_s,
             "publication cap in messages per wall second (0 = none); past it the simulation "
             "slows down rather than flood subscribers");
    process::AddSourceFlowOptions(app, o.flow);
    app.add_option("--truth-out", o.truth_out, "write the truth sidecar JSON to this file");
    AddShown(app, "--seed", raw.seed, "random seed: same seed, same output");
    AddShown(app, "--noise-seed", raw.noise_seed,
             "seed of the noise alone (0 = --seed): the same units, another realisation");
}

// Which units, of which module, sampled how.
void AddUnitOptions(CLI::App& app, sim::RigConfig& r, RawOptions& raw) {
    AddShown(app, "--units", r.num_units, "number of units S01..S<n>, 1..256");
    app.add_option("--sensor-ids", raw.sensor_ids_text,
                   "comma-separated unit ids (overrides --units)");
    AddShown(app, "--preset", raw.preset,
             "gyro module: 610 (ADXRS610, +-300 deg/s, 6 mV/(deg/s)) or 613 (ADXRS613, +-150 "
             "deg/s, 12.5 mV/(deg/s))");
    app.add_option("--temp-v-at-25c", raw.temp_v_at_25c,
                   "temperature line at 25 degC [V] (default: the preset's, 2.5)");
    app.add_option("--temp-v-per-c", raw.temp_v_per_c,
                   "temperature line slope [V/degC] (default: the preset's, 0.009)");
    AddShown(app, "--rate-hz", r.sample_rate_hz, "gyro sample rate [Hz]");
    AddShown(app, "--start-utime", raw.start_utime, "simulated clock at power-on [us]");
    app.add_option("--effect", raw.effects, "undeclared effect NAME=VALUE (see below), repeatable");
}

void AddNoiseOptions(CLI::App& app, sim::NoiseConfig& n) {
    AddRenamed(app, "--noise-density-dps-rthz", "--noise-density", n.noise_density_dps_rthz,
               "white rate noise [deg/s/sqrt(Hz)] (Allan dev = value/sqrt(tau))");
    AddShown(app, "--bias-instability-dps", n.bias_instability_dps,
             "flat Allan-deviation level [deg/s]");
    AddShown(app, "--rrw-dps-rts", n.rate_random_walk_dps_rts, "rate random walk [deg/s/sqrt(s)]");
    AddShown(app, "--lpf-hz", n.lpf_hz, "module output low-pass corner [Hz], 0 = none");
    AddShown(app, "--temp-noise-v", n.temp_noise_v, "temperature line noise [V]");
}

void AddThermalOptions(CLI::App& app, sim::RigConfig& r) {
    AddShown(app, "--start-temp-c", r.thermal.start_temp_c, "chamber and units at power-on [degC]");
    AddShown(app, "--ramp-c-per-min", r.thermal.ramp_c_per_min,
             "chamber ramp-rate limit [degC/min]");
    AddShown(app, "--air-tau-s", r.thermal.air_tau_s, "air settling lag [s]");
    AddShown(app, "--air-noise-c", r.thermal.air_noise_c, "air control fluctuation [degC]");
    AddShown(app, "--package-tau-s", r.thermal.package_tau_s, "die lag behind the air [s]");
    AddRenamed(app, "--package-tau-spread-frac", "--package-tau-spread",
               r.spread.package_tau_spread_frac, "per-unit relative spread of the package lag");
    AddShown(app, "--sensor-tau-s", r.thermal.sensor_tau_s,
             "temperature sensor lag behind the die [s]");
    AddShown(app, "--temp-sensor-offset-std-c", r.spread.temp_sensor_offset_std_c,
             "per-unit temperature sensor offset spread [degC]");
    AddShown(app, "--setpoint-tolerance-c", r.thermal.setpoint_tolerance_c,
             "at_setpoint band [degC]");
    AddShown(app, "--min-setpoint-c", r.thermal.min_setpoint_c, "lowest accepted setpoint [degC]");
    AddShown(app, "--max-setpoint-c", r.thermal.max_setpoint_c, "highest accepted setpoint [degC]");
}

// The turntable, its encoder, the ADC and the supply.
void AddHardwareOptions(CLI::App& app, sim::RigConfig& r) {
    AddShown(app, "--table-rate-dps", r.table.default_rate_dps, "default cruise rate [deg/s]");
    AddShown(app, "--table-accel-dps2", r.table.default_accel_dps2,
             "default acceleration [deg/s^2]");
    AddShown(app, "--table-max-rate-dps", r.table.max_rate_dps,
             "faster orders are refused [deg/s]");
    AddShown(app, "--encoder-lines", r.encoder.lines_per_rev, "encoder lines per revolution");
    AddShown(app, "--encoder-quadrature", r.encoder.quadrature, "counts per line: 1, 2 or 4");
    AddShown(app, "--encoder-hz", r.encoder.rate_hz, "encoder publication rate [Hz]");
    AddShown(app, "--adc-bits", r.adc.bits, "ADC resolution, 0 = no ADC (analog volts)");
    AddShown(app, "--adc-vref-v", r.adc.vref_v, "ADC full scale [V]");
    AddShown(app, "--supply-ripple-v", r.supply.ripple_v, "supply ripple amplitude [V]");
    AddShown(app, "--supply-drift-std-v", r.supply.drift_std_v, "supply slow drift [V]");
}

// The effects' shapes and the built-in profile.
void AddShapeAndProfileOptions(CLI::App& app, SimRigOptions& o, RawOptions& raw) {
    AddShown(app, "--hysteresis-width-c", o.rig.effects.hysteresis_width_c,
             "reversal that switches branch [degC]");
    AddShown(app, "--warmup-tau-s", o.rig.effects.warmup_tau_s,
             "warm-up transient time constant [s]");
    AddShown(app, "--profile", raw.profile_text, "builtin mode: setpoints [degC], comma-separated");
    AddShown(app, "--dwell-s", o.profile.dwell_s,
             "builtin mode: time at setpoint before rotating [s]");
    AddShown(app, "--rest-s", o.profile.rest_s, "builtin mode: rest after each move [s]");
    AddShown(app, "--move-deg", o.profile.move_deg, "builtin mode: rotation (+ then -) [deg]");
}

// The preset, then the explicit temperature transfer over it: the transfer function both
// simulates the sensor line and converts it to temp_c.
void ResolvePreset(const RawOptions& raw, sim::GyroPreset& preset) {
    preset = sim::PresetByName(raw.preset);
    if (!std::isnan(raw.temp_v_at_25c)) {
        if (!std::isfinite(raw.temp_v_at_25c) || raw.temp_v_at_25c <= 0.0 ||
            raw.temp_v_at_25c >= 50.0) {
            throw sim::ConfigError("--temp-v-at-25c is out of range; valid: > 0 and < 50 V");
        }
        preset.temp_transfer.v_at_25c = raw.temp_v_at_25c;
    }
    if (!std::isnan(raw.temp_v_per_c)) {
        if (!std::isfinite(raw.temp_v_per_c) || raw.temp_v_per_c <= 0.0 || raw.temp_v_per_c > 1.0) {
            throw sim::ConfigError("--temp-v-per-c is out of range; valid: > 0 and <= 1 V/degC");
        }
        preset.temp_transfer.v_per_c = raw.temp_v_per_c;
    }
}

// The process's own options (mode, pacing, built-in profile): ConfigError names the first bad one.
void CheckRunOptions(const SimRigOptions& o) {
    using sim::ConfigError;
    if (o.mode != "commanded" && o.mode != "builtin") {
        throw ConfigError("--mode '" + o.mode + "' is unknown; valid: commanded, builtin");
    }
    if (!std::isfinite(o.speed) || o.speed < 0.0 || o.speed > 100000.0) {
        std::ostringstream v;
        v << o.speed;
        throw ConfigError("--speed " + v.str() +
                          " is out of range; valid: 0 (as fast as the consumers keep up) or > 0 "
                          "and <= 100000 (simulated s per wall s)");
    }
    if (std::string e = o.flow.Validate(); !e.empty()) throw ConfigError(e);
    if (!std::isfinite(o.duration_s) || o.duration_s < 0.0) {
        throw ConfigError("--duration-s must be >= 0 (0 = until stopped)");
    }
    if (!std::isfinite(o.max_msgs_per_s) || o.max_msgs_per_s < 0.0) {
        throw ConfigError("--max-msgs-per-s must be >= 0 (0 = no cap)");
    }
    if (!std::isfinite(o.tick_ms) || o.tick_ms < 1.0 || o.tick_ms > 100.0) {
        throw ConfigError("--tick-ms is out of range; valid: 1 .. 100");
    }
    if (!(o.profile.dwell_s >= 0.0) || !(o.profile.rest_s >= 0.0) ||
        !std::isfinite(o.profile.move_deg) ||
        std::abs(o.profile.move_deg) > o.rig.table.max_move_deg) {
        throw ConfigError("--dwell-s, --rest-s must be >= 0 and |--move-deg| <= the table's limit");
    }
}

// The values CLI11 cannot check alone, into `o`: "" when valid, else the ConfigError's one-line
// reason (exit 2).
std::string ResolveOptions(const RawOptions& raw, SimRigOptions& o) {
    sim::RigConfig& r = o.rig;
    try {
        r.seed = raw.seed;
        r.noise_seed = raw.noise_seed;
        r.start_utime = raw.start_utime;
        ResolvePreset(raw, r.preset);
        if (!raw.sensor_ids_text.empty()) {
            std::stringstream ss(raw.sensor_ids_text);
            std::string id;
            while (std::getline(ss, id, ',')) r.sensor_ids.push_back(id);
        }
        for (const auto& e : raw.effects) sim::ParseEffect(r.effects, e);
        CheckRunOptions(o);
        o.profile.setpoints_c = sim::ParseProfile(raw.profile_text, r.thermal);
        r.Validate();
    } catch (const sim::ConfigError& e) {
        return e.what();
    }
    return "";
}

std::optional<int> ParseInto(CLI::App& app, int argc, char** argv, SimRigOptions& o) {
    RawOptions raw;
    raw.preset = o.rig.preset.name;
    raw.start_utime = o.rig.start_utime;
    raw.seed = o.rig.seed;
    raw.noise_seed = o.rig.noise_seed;
    AddRunOptions(app, o, raw);
    AddUnitOptions(app, o.rig, raw);
    AddNoiseOptions(app, o.rig.noise);
    AddThermalOptions(app, o.rig);
    AddHardwareOptions(app, o.rig);
    AddShapeAndProfileOptions(app, o, raw);
    app.footer(kFooter);
    return process::ParseCommandLine(app, argc, argv, "gyrocal-sim-rig",
                                     [&] { return ResolveOptions(raw, o); });
}

}  // namespace

std::optional<int> ParseSimRigOptions(int argc, char** argv, SimRigOptions& options) {
    CLI::App app{
        "gyrocal-sim-rig: simulated temperature chamber, turntable, encoder and gyro "
        "modules; publishes GYRO_<id>, ENCODER, CHAMBER_STATE, obeys CHAMBER_CMD and "
        "TURNTABLE_CMD",
        "gyrocal-sim-rig"};
    options = SimRigOptions::Defaults();
    return ParseInto(app, argc, argv, options);
}

}  // namespace gyrocal::sim_rig
