#include "cli.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "runtime/process_main.hpp"
#include "sim/builtin_profile.hpp"

namespace gyrocal {

namespace {

// The measured limit, stated in --help (see tests/bench/producers_sim and the report).
const char* kFooter = R"(
Exit codes: 0 normal stop (SIGINT/SIGTERM, --duration-s reached, built-in profile done),
            1 runtime failure (LCM cannot be opened or fails), 2 bad options/configuration.

Time: utime is the simulated clock (us), starting at --start-utime; the wall clock only paces
publication: --speed simulated seconds per wall second, published in batches every --tick-ms.
Speed limit, measured with tests/bench/producers_sim/gyrocal_bench_sim_rig_bus (the real rig
and one subscriber on the same host, 2-core AMD EPYC shared with other builds): 4 units at
100 Hz plus the encoder at 100 Hz are 500 messages per simulated second. Uncapped, the rig sent
~70k messages/s (--speed ~140) with 0 lost at load ~4, but at load ~11 it lost 1-3 % of samples
from 32k messages/s up. With the default cap of 30000 messages/s (--speed 60 for 4 units) 0 were
lost at load ~11. UDP multicast has no flow control: with more subscribers or a busier host,
lower --max-msgs-per-s; past the cap the simulation just runs slower (STATUS extra lag_s),
never skipping a sample. The simulation alone generates ~11M samples/s (4 units).
The WHOLE pipeline (rig, plateau, rotation, fitter, compensator publishing RATE_ for every
sample, recorder, sequencer: 7 processes each receiving every packet of the group), measured
with `gyrocal calibrate` on the same machine: 4 units at --speed 30 (15000 rig messages/s) lost
0 samples at load ~6; at --speed 60 (30000/s) every process lost 1-2 % at load ~9. So the
fastest lossless speed of the whole pipeline here is ~15000 rig messages/s: --speed 30 for 4
units, 75 for 1; `gyrocal calibrate` picks that by default.

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

std::optional<int> ParseInto(CLI::App& app, int argc, char** argv, SimRigOptions& o) {
    using sim::ConfigError;
    auto& r = o.rig;
    std::string preset = r.preset.name;
    double temp_v_at_25c = NAN, temp_v_per_c = NAN;  // NaN = the preset's
    std::string profile_text = "-10,30,60";
    std::string sensor_ids_text;
    std::vector<std::string> effects;
    long long start_utime = r.start_utime;
    unsigned long long seed = r.seed;
    unsigned long long noise_seed = r.noise_seed;

    app.add_option("--lcm-url", o.lcm_url,
                   "LCM provider URL (default $GYROCAL_LCM_URL or LCM's udpm default)");
    app.add_option("--mode", o.mode,
                   "commanded (obey CHAMBER_CMD/TURNTABLE_CMD) or builtin (run --profile)")
        ->capture_default_str();
    app.add_option("--speed", o.speed, "simulated seconds per wall second, > 0 and <= 100000")
        ->capture_default_str();
    app.add_option("--duration-s", o.duration_s, "simulated seconds to run, 0 = until stopped")
        ->capture_default_str();
    app.add_option("--tick-ms", o.tick_ms, "wall milliseconds between publication batches, 1..100")
        ->capture_default_str();
    app.add_option("--max-msgs-per-s", o.max_msgs_per_s,
                   "publication cap in messages per wall second (0 = none); past it the simulation "
                   "slows down rather than flood subscribers")
        ->capture_default_str();
    app.add_option("--truth-out", o.truth_out, "write the truth sidecar JSON to this file");
    app.add_option("--seed", seed, "random seed: same seed, same output")->capture_default_str();
    app.add_option("--noise-seed", noise_seed,
                   "seed of the noise alone (0 = --seed): the same units, another realisation")
        ->capture_default_str();
    app.add_option("--units", r.num_units, "number of units S01..S<n>, 1..256")
        ->capture_default_str();
    app.add_option("--sensor-ids", sensor_ids_text, "comma-separated unit ids (overrides --units)");
    app.add_option("--preset", preset,
                   "gyro module: 610 (ADXRS610, +-300 deg/s, 6 mV/(deg/s)) or 613 (ADXRS613, +-150 "
                   "deg/s, 12.5 mV/(deg/s))")
        ->capture_default_str();
    app.add_option("--temp-v-at-25c", temp_v_at_25c,
                   "temperature line at 25 degC [V] (default: the preset's, 2.5)");
    app.add_option("--temp-v-per-c", temp_v_per_c,
                   "temperature line slope [V/K] (default: the preset's, 0.009)");
    app.add_option("--rate-hz", r.sample_rate_hz, "gyro sample rate [Hz]")->capture_default_str();
    app.add_option("--start-utime", start_utime, "simulated clock at power-on [us]")
        ->capture_default_str();
    app.add_option("--effect", effects, "undeclared effect NAME=VALUE (see below), repeatable");
    // Noise
    app.add_option("--noise-density", r.noise.noise_density_dps_rthz,
                   "white rate noise [deg/s/sqrt(Hz)] (Allan dev = value/sqrt(tau))")
        ->capture_default_str();
    app.add_option("--bias-instability-dps", r.noise.bias_instability_dps,
                   "flat Allan-deviation level [deg/s]")
        ->capture_default_str();
    app.add_option("--rrw-dps-rts", r.noise.rate_random_walk_dps_rts,
                   "rate random walk [deg/s/sqrt(s)]")
        ->capture_default_str();
    app.add_option("--lpf-hz", r.noise.lpf_hz, "module output low-pass corner [Hz], 0 = none")
        ->capture_default_str();
    app.add_option("--temp-noise-v", r.noise.temp_noise_v, "temperature line noise [V]")
        ->capture_default_str();
    // Thermal
    app.add_option("--start-temp-c", r.thermal.start_temp_c, "chamber and units at power-on [degC]")
        ->capture_default_str();
    app.add_option("--ramp-c-per-min", r.thermal.ramp_c_per_min,
                   "chamber ramp-rate limit [degC/min]")
        ->capture_default_str();
    app.add_option("--air-tau-s", r.thermal.air_tau_s, "air settling lag [s]")
        ->capture_default_str();
    app.add_option("--air-noise-c", r.thermal.air_noise_c, "air control fluctuation [degC]")
        ->capture_default_str();
    app.add_option("--package-tau-s", r.thermal.package_tau_s, "die lag behind the air [s]")
        ->capture_default_str();
    app.add_option("--package-tau-spread", r.spread.package_tau_spread_frac,
                   "per-unit relative spread of the package lag")
        ->capture_default_str();
    app.add_option("--sensor-tau-s", r.thermal.sensor_tau_s,
                   "temperature sensor lag behind the die [s]")
        ->capture_default_str();
    app.add_option("--temp-sensor-offset-std-c", r.spread.temp_sensor_offset_std_c,
                   "per-unit temperature sensor offset spread [degC]")
        ->capture_default_str();
    app.add_option("--setpoint-tolerance-c", r.thermal.setpoint_tolerance_c,
                   "at_setpoint band [degC]")
        ->capture_default_str();
    app.add_option("--min-setpoint-c", r.thermal.min_setpoint_c, "lowest accepted setpoint [degC]")
        ->capture_default_str();
    app.add_option("--max-setpoint-c", r.thermal.max_setpoint_c, "highest accepted setpoint [degC]")
        ->capture_default_str();
    // Table and encoder
    app.add_option("--table-rate-dps", r.table.default_rate_dps, "default cruise rate [deg/s]")
        ->capture_default_str();
    app.add_option("--table-accel-dps2", r.table.default_accel_dps2,
                   "default acceleration [deg/s^2]")
        ->capture_default_str();
    app.add_option("--table-max-rate-dps", r.table.max_rate_dps,
                   "faster orders are refused [deg/s]")
        ->capture_default_str();
    app.add_option("--encoder-lines", r.encoder.lines_per_rev, "encoder lines per revolution")
        ->capture_default_str();
    app.add_option("--encoder-quadrature", r.encoder.quadrature, "counts per line: 1, 2 or 4")
        ->capture_default_str();
    app.add_option("--encoder-hz", r.encoder.rate_hz, "encoder publication rate [Hz]")
        ->capture_default_str();
    // ADC and supply
    app.add_option("--adc-bits", r.adc.bits, "ADC resolution, 0 = no ADC (analog volts)")
        ->capture_default_str();
    app.add_option("--adc-vref-v", r.adc.vref_v, "ADC full scale [V]")->capture_default_str();
    app.add_option("--supply-ripple-v", r.supply.ripple_v, "supply ripple amplitude [V]")
        ->capture_default_str();
    app.add_option("--supply-drift-std-v", r.supply.drift_std_v, "supply slow drift [V]")
        ->capture_default_str();
    // Effects' shapes
    app.add_option("--hysteresis-width-c", r.effects.hysteresis_width_c,
                   "reversal that switches branch [degC]")
        ->capture_default_str();
    app.add_option("--warmup-tau-s", r.effects.warmup_tau_s, "warm-up transient time constant [s]")
        ->capture_default_str();
    // Built-in profile
    app.add_option("--profile", profile_text, "builtin mode: setpoints [degC], comma-separated")
        ->capture_default_str();
    app.add_option("--dwell-s", o.profile.dwell_s,
                   "builtin mode: time at setpoint before rotating [s]")
        ->capture_default_str();
    app.add_option("--rest-s", o.profile.rest_s, "builtin mode: rest after each move [s]")
        ->capture_default_str();
    app.add_option("--move-deg", o.profile.move_deg, "builtin mode: rotation (+ then -) [deg]")
        ->capture_default_str();
    app.footer(kFooter);

    // The values CLI11 cannot check alone: their ConfigError is the one-line reason (exit 2).
    const auto validate = [&]() -> std::string {
        try {
            r.seed = seed;
            r.noise_seed = noise_seed;
            r.start_utime = start_utime;
            r.preset = sim::PresetByName(preset);
            // The transfer function both simulates the sensor line and converts it to temp_c.
            if (!std::isnan(temp_v_at_25c)) {
                if (!std::isfinite(temp_v_at_25c) || temp_v_at_25c <= 0.0 ||
                    temp_v_at_25c >= 50.0) {
                    throw sim::ConfigError(
                        "--temp-v-at-25c is out of range; valid: > 0 and < 50 V");
                }
                r.preset.temp_transfer.v_at_25c = temp_v_at_25c;
            }
            if (!std::isnan(temp_v_per_c)) {
                if (!std::isfinite(temp_v_per_c) || temp_v_per_c <= 0.0 || temp_v_per_c > 1.0) {
                    throw sim::ConfigError(
                        "--temp-v-per-c is out of range; valid: > 0 and <= 1 V/K");
                }
                r.preset.temp_transfer.v_per_k = temp_v_per_c;
            }
            if (!sensor_ids_text.empty()) {
                std::stringstream ss(sensor_ids_text);
                std::string id;
                while (std::getline(ss, id, ',')) r.sensor_ids.push_back(id);
            }
            for (const auto& e : effects) sim::ParseEffect(r.effects, e);
            if (o.mode != "commanded" && o.mode != "builtin") {
                throw ConfigError("--mode '" + o.mode + "' is unknown; valid: commanded, builtin");
            }
            if (!std::isfinite(o.speed) || o.speed <= 0.0 || o.speed > 100000.0) {
                std::ostringstream v;
                v << o.speed;
                throw ConfigError(
                    "--speed " + v.str() +
                    " is out of range; valid: > 0 and <= 100000 (simulated s per wall s)");
            }
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
                std::abs(o.profile.move_deg) > r.table.max_move_deg) {
                throw ConfigError(
                    "--dwell-s, --rest-s must be >= 0 and |--move-deg| <= the table's limit");
            }
            o.profile.setpoints_c = sim::ParseProfile(profile_text, r.thermal);
            r.Validate();
        } catch (const ConfigError& e) {
            return e.what();
        }
        return "";
    };
    return ParseCommandLine(app, argc, argv, "gyrocal-sim-rig", validate);
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

}  // namespace gyrocal
